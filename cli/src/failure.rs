//! Why a command failed, printed as one `error: …` line (the message of the library error,
//! which already names the file, the place and the problem).

use std::fmt::Display;

/// A failed command: exit status 1.
#[derive(Debug)]
pub struct Failure(String);

impl Failure {
    pub fn report(&self) {
        eprintln!("error: {}", self.0);
    }
}

impl<E: Display> From<E> for Failure {
    fn from(e: E) -> Failure {
        Failure(e.to_string())
    }
}
