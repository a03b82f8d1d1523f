//! Errors of identification: every one names what is wrong and where (file, line, column,
//! joint or parameter), so a bad input never turns into a silent wrong estimate. An error that
//! comes from below (reading the file, the CSV reader, the model) keeps it as its source.

use std::fmt;
use std::path::{Path, PathBuf};

/// Why identification (or reading its data) failed. Formatted like the description loader's
/// errors: `file:line: column c (name): message`.
#[derive(Debug, thiserror::Error)]
pub enum IdentifyError {
    /// The data file could not be opened or read.
    #[error("{}: cannot read the data file: {source}", path.display())]
    Read { path: PathBuf, source: std::io::Error },
    /// The CSV reader failed (a line that is not UTF-8, an unterminated quote).
    #[error("{place}not valid CSV: {source}")]
    Csv { place: Place, source: csv::Error },
    /// The data is wrong: a column, a field, the time, a limit, too few samples to filter.
    #[error("{place}{message}")]
    Data { place: Place, message: String },
    /// The data cannot determine the parameters (too few samples, a parameter not excited).
    #[error("{0}")]
    Unidentifiable(String),
    /// A closed-loop estimator (IDIM-IV, DIDIM) did not settle: its simulated loop diverged,
    /// its steps grew, or it did not converge.
    #[error("{0}")]
    Diverged(String),
    /// A compiled robot given as the regressor source is not the description's robot.
    #[error("{0}")]
    WrongRobot(String),
    /// No identified description loads back, not even the description identification
    /// started from with the least squares' joint terms: a bug, said as one.
    #[error("internal error: no identified description loads back: {0}")]
    InvalidEstimate(String),
}

/// Where in the data an error is: file, line, and the CSV field (1-based column, not character)
/// with its header name. Each part is optional; it prints as the message's prefix.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Place {
    pub file: Option<PathBuf>,
    pub line: Option<usize>,
    pub column: Option<(usize, String)>,
}

impl fmt::Display for Place {
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
        Ok(())
    }
}

impl IdentifyError {
    /// A data error without a place yet (the reader adds line, column and file as it knows them).
    pub(crate) fn data(message: impl Into<String>) -> Self {
        IdentifyError::Data {
            place: Place::default(),
            message: message.into(),
        }
    }

    fn place_mut(&mut self) -> Option<&mut Place> {
        match self {
            IdentifyError::Data { place, .. } | IdentifyError::Csv { place, .. } => Some(place),
            _ => None,
        }
    }

    pub(crate) fn in_file(mut self, file: &Path) -> Self {
        if let Some(place) = self.place_mut() {
            place.file = Some(file.to_path_buf());
        }
        self
    }

    pub(crate) fn at_line(mut self, line: usize) -> Self {
        if let Some(place) = self.place_mut() {
            place.line = Some(line);
        }
        self
    }

    pub(crate) fn at_column(mut self, column: usize, name: &str) -> Self {
        if let Some(place) = self.place_mut() {
            place.column = Some((column, name.to_owned()));
        }
        self
    }
}
