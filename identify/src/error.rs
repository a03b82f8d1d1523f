//! Errors of identification: every one names what is wrong and where (file, line, column,
//! joint or parameter), so a bad input never turns into a silent wrong estimate.

use std::fmt;
use std::path::{Path, PathBuf};

/// An identification error, formatted like the description loader's: `file:line:column: message`.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyError {
    pub file: Option<PathBuf>,
    pub line: Option<usize>,
    /// 1-based column of the CSV field (not of the character), with its header name.
    pub column: Option<(usize, String)>,
    pub message: String,
}

impl IdentifyError {
    pub fn new(message: impl Into<String>) -> Self {
        IdentifyError {
            file: None,
            line: None,
            column: None,
            message: message.into(),
        }
    }

    pub fn in_file(mut self, file: &Path) -> Self {
        self.file = Some(file.to_path_buf());
        self
    }

    pub fn at_line(mut self, line: usize) -> Self {
        self.line = Some(line);
        self
    }

    pub fn at_column(mut self, column: usize, name: &str) -> Self {
        self.column = Some((column, name.to_owned()));
        self
    }
}

impl fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some(line) = self.line {
                write!(f, ":{line}")?;
            }
            write!(f, ": ")?;
        } else if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        if let Some((column, name)) = &self.column {
            write!(f, "column {column} ({name}): ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for IdentifyError {}
