//! Where each item of a description is in its file, so that checks made long after parsing
//! (a zero axis, a cycle, an undefined link) can still point at a line and column.
//!
//! Places are keyed by a path in the YAML shape, the same shape serde uses in its own
//! messages: `joints[3].axis`, `links[0].inertial.mass`, `locked_joints.finger`. The URDF
//! reader records its elements under the same paths, so the checks need not know the format.

use super::error::{render, DescriptionError, Location};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Paths of one description file, mapped to their places in it.
#[derive(Clone, Debug, Default)]
pub(crate) struct SourceMap {
    pub file: PathBuf,
    places: HashMap<String, Location>,
    /// Places of mapping keys (YAML only), by the path of their value.
    keys: HashMap<String, Location>,
}

impl SourceMap {
    pub fn new(file: &Path) -> Self {
        SourceMap {
            file: file.to_path_buf(),
            places: HashMap::new(),
            keys: HashMap::new(),
        }
    }

    /// Records a place; the first record of a path wins.
    pub fn insert(&mut self, path: String, location: Location) {
        self.places.entry(path).or_insert(location);
    }

    /// Records the place of the key whose value is at `path`; the first record wins.
    pub fn insert_key(&mut self, path: String, location: Location) {
        self.keys.entry(path).or_insert(location);
    }

    /// An error about the key whose value is at `path` (an unknown key, a key chosen twice),
    /// at the key; else as [`SourceMap::error`].
    pub fn key_error(&self, path: &str, message: impl Into<String>) -> DescriptionError {
        let at = self.keys.get(path).copied().or_else(|| self.locate(path));
        DescriptionError::new(&self.file, message).at(at)
    }

    /// The place of `path`, or of the nearest enclosing path that has one
    /// (`joints[3].limit.lower` → `joints[3].limit` → `joints[3]`).
    pub fn locate(&self, path: &str) -> Option<Location> {
        let mut path = path;
        loop {
            if let Some(loc) = self.places.get(path) {
                return Some(*loc);
            }
            let cut = path.rfind(['.', '['])?;
            path = &path[..cut];
        }
    }

    /// An error about the item at `path`.
    pub fn error(&self, path: &str, message: impl Into<String>) -> DescriptionError {
        DescriptionError::new(&self.file, message).at(self.locate(path))
    }

    /// A warning or note about the item at `path`, formatted like an error.
    pub fn diagnostic(&self, path: &str, item: Option<&str>, message: &str) -> String {
        render(&self.file, self.locate(path), item, message)
    }
}

/// Path of the `i`-th link of a description.
pub(crate) fn link_path(i: usize) -> String {
    format!("links[{i}]")
}

/// Path of the `i`-th joint of a description.
pub(crate) fn joint_path(i: usize) -> String {
    format!("joints[{i}]")
}

/// Reads a description: a regular file only (`/dev/zero` or a FIFO would never end), UTF-8.
pub(crate) fn read_regular_file(path: &Path) -> std::io::Result<String> {
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        ));
    }
    std::fs::read_to_string(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_falls_back_to_enclosing_paths() {
        let mut map = SourceMap::new(Path::new("f.yaml"));
        map.insert("joints[1]".into(), Location { line: 7, column: 5 });
        map.insert("joints[1].axis".into(), Location { line: 9, column: 11 });
        assert_eq!(
            map.locate("joints[1].axis"),
            Some(Location { line: 9, column: 11 })
        );
        assert_eq!(
            map.locate("joints[1].limit.lower"),
            Some(Location { line: 7, column: 5 })
        );
        assert_eq!(map.locate("joints[2].axis"), None);
        assert_eq!(map.locate(""), None);
    }
}
