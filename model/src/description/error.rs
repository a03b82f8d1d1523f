//! The one error type of the loaders, and the formatting shared with warnings and notes.
//!
//! A message must let a person fix the file without reading our code: it names the file, the
//! place (line:column, as editors and terminals understand it), the item (`joint 'j2'`) and
//! the problem, on one line.

use std::fmt;
use std::path::{Path, PathBuf};

/// Warnings and notes gathered along the way, already formatted like errors.
#[derive(Debug, Default)]
pub(crate) struct Diagnostics {
    pub warnings: Vec<String>,
    pub notes: Vec<String>,
}

/// A place in a text file, both counted from 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Location {
    pub line: usize,
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// A robot description that cannot be turned into a model.
///
/// Displays as `file:line:column: item: message`, e.g.
/// `robots/arm7.yaml:42:11: joint 'joint3': axis [0, 0, 0] has zero length`; the location and
/// the item are left out when unknown.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", render(file, *location, item.as_deref(), message))]
pub struct DescriptionError {
    /// The file the problem is in (as given by the caller, or resolved from a YAML `urdf:`);
    /// for a robot in memory, a label that names it, e.g. `<urdf_rs::Robot 'panda'>`.
    pub file: PathBuf,
    /// Where in the file, when known.
    pub location: Option<Location>,
    /// The element concerned, e.g. `joint 'j2'` or `link 'l3'`.
    pub item: Option<String>,
    /// What is wrong, as a sentence fragment.
    pub message: String,
}

impl DescriptionError {
    pub fn new(file: &Path, message: impl Into<String>) -> Self {
        DescriptionError {
            file: file.to_path_buf(),
            location: None,
            item: None,
            message: message.into(),
        }
    }

    pub(crate) fn at(mut self, location: Option<Location>) -> Self {
        self.location = location;
        self
    }

    pub(crate) fn about(mut self, item: impl Into<String>) -> Self {
        self.item = Some(item.into());
        self
    }
}

/// `file:line:col: item: message`, the shape compilers use, so editors can jump to it.
pub(crate) fn render(file: &Path, location: Option<Location>, item: Option<&str>, message: &str) -> String {
    let mut s = file.display().to_string();
    if let Some(loc) = location {
        s.push_str(&format!(":{loc}"));
    }
    s.push_str(": ");
    if let Some(item) = item {
        s.push_str(item);
        s.push_str(": ");
    }
    s.push_str(message);
    s
}

/// `joint 'name'`, `link 'name'`: how messages name an element.
pub(crate) fn item(kind: &str, name: &str) -> String {
    format!("{kind} '{name}'")
}

/// A number for a message: shortest round-trip form (`0.1`, `-2.96`, `NaN`, `inf`), with an
/// exponent when very large or small (`1e308`, not 309 digits).
pub(crate) fn num(v: f64) -> String {
    let a = v.abs();
    if v.is_finite() && v != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A vector for a message: `[0, 0, 1]`.
pub(crate) fn vec3(v: &[f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}
