//! Line and column of every node of a YAML document, by path.
//!
//! serde gives a place only for its own errors; checks made after deserialization (a zero
//! axis, an undefined parent link) need the place of the offending node too. A second,
//! event-level pass over the text records where each node starts. It only informs messages:
//! if it disagrees with serde or fails, messages lose their line and column, nothing else.

use super::error::Location;
use super::source_map::SourceMap;
use saphyr_parser::{Event, Parser, Span, SpannedEventReceiver};
use std::path::Path;

/// Records the place of every node of the first document of `text` under its path
/// (`joints[3].axis`, `locked_joints.finger_joint1`).
pub(crate) fn index(text: &str, file: &Path) -> SourceMap {
    let mut rec = Recorder {
        map: SourceMap::new(file),
        stack: Vec::new(),
        done: false,
    };
    let mut parser = Parser::new_from_str(text);
    // A syntax error ends the pass; serde reports it with its own place.
    let _ = parser.load(&mut rec, false);
    rec.map
}

/// An open container and where the next node in it goes.
enum Open {
    /// A mapping: `key` is the last key seen (`None` while the next node is a key, or when
    /// the key is not a plain scalar and its value has no path).
    Map {
        path: Option<String>,
        key: Option<String>,
        expecting_key: bool,
    },
    Seq {
        path: Option<String>,
        next: usize,
    },
}

struct Recorder {
    map: SourceMap,
    stack: Vec<Open>,
    done: bool,
}

impl Recorder {
    /// Handles a node: records its place and returns its path, or `None` when it is a
    /// mapping key (keys name paths, they are not nodes of their own here) or has no path.
    fn node(&mut self, key_text: Option<&str>, span: Span) -> Option<String> {
        let location = Location {
            line: span.start.line(),
            column: span.start.col() + 1,
        };
        let path = match self.stack.last_mut() {
            None => Some(String::new()),
            Some(Open::Map {
                path,
                key,
                expecting_key,
            }) => {
                if *expecting_key {
                    *expecting_key = false;
                    *key = key_text.map(str::to_owned);
                    if let (Some(p), Some(k)) = (path.as_ref(), key.as_ref()) {
                        let at = match p.is_empty() {
                            true => k.clone(),
                            false => format!("{p}.{k}"),
                        };
                        self.map.insert_key(at, location);
                    }
                    return None;
                }
                *expecting_key = true;
                match (path.as_ref(), key.take()) {
                    (Some(p), Some(k)) if p.is_empty() => Some(k),
                    (Some(p), Some(k)) => Some(format!("{p}.{k}")),
                    _ => None,
                }
            }
            Some(Open::Seq { path, next }) => {
                let i = *next;
                *next += 1;
                path.as_ref().map(|p| format!("{p}[{i}]"))
            }
        };
        if let Some(p) = &path {
            if !p.is_empty() {
                self.map.insert(p.clone(), location);
            }
        }
        path
    }

    /// Whether the next node is a mapping key (a container in key position gets no path).
    fn expecting_key(&self) -> bool {
        matches!(
            self.stack.last(),
            Some(Open::Map {
                expecting_key: true,
                ..
            })
        )
    }
}

impl<'input> SpannedEventReceiver<'input> for Recorder {
    fn on_event(&mut self, ev: Event<'input>, span: Span) {
        if self.done {
            return;
        }
        match ev {
            Event::Scalar(text, ..) => {
                self.node(Some(&text), span);
            }
            Event::Alias(_) => {
                self.node(None, span);
            }
            Event::MappingStart(..) | Event::SequenceStart(..) => {
                let is_key = self.expecting_key();
                let path = self.node(None, span).filter(|_| !is_key);
                self.stack.push(match ev {
                    Event::MappingStart(..) => Open::Map {
                        path,
                        key: None,
                        expecting_key: true,
                    },
                    _ => Open::Seq { path, next: 0 },
                });
            }
            Event::MappingEnd | Event::SequenceEnd => {
                self.stack.pop();
            }
            Event::DocumentEnd => self.done = true,
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_and_flow_nodes_get_their_places() {
        let text = "name: x\njoints:\n  - name: j1\n    axis: [0, 0, 1]\n  - {name: j2, axis: [1, 0, 0]}\nlocked_joints: {f1: 0.0}\n";
        let map = index(text, Path::new("f.yaml"));
        let at = |p: &str| map.locate(p).map(|l| (l.line, l.column));
        assert_eq!(at("name"), Some((1, 7)));
        assert_eq!(at("joints[0]"), Some((3, 5)));
        assert_eq!(at("joints[0].axis"), Some((4, 11)));
        assert_eq!(at("joints[0].axis[2]"), Some((4, 18)));
        assert_eq!(at("joints[1]"), Some((5, 5)));
        assert_eq!(at("joints[1].axis"), Some((5, 22)));
        assert_eq!(at("locked_joints.f1"), Some((6, 21)));
        let key = |p: &str| map.key_error(p, "").location.map(|l| (l.line, l.column));
        assert_eq!(key("locked_joints"), Some((6, 1)));
        assert_eq!(key("locked_joints.f1"), Some((6, 17)));
        assert_eq!(key("joints[1].axis"), Some((5, 16)));
    }

    #[test]
    fn broken_text_gives_a_partial_map() {
        let map = index("a: 1\nb: [\n", Path::new("f.yaml"));
        assert_eq!(map.locate("a").map(|l| l.line), Some(1));
    }
}
