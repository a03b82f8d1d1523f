//! Scratch directories for tests that write files.

/// A fresh directory under the system's temporary directory, named `dyngen-<name>-…`, removed
/// with everything in it when dropped (also when the test panics).
pub fn scratch_dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("dyngen-{name}-"))
        .tempdir()
        .expect("a scratch directory under the system's temporary directory")
}
