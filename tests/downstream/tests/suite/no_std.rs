//! Generated code links into a `#![no_std]` crate (`tests/nostd/`): a static library that wraps the
//! committed arm7 and defines its own `#[panic_handler]`, which fails to build with "duplicate
//! lang item `panic_impl`" if the runtime contract, nalgebra (without default features) or the
//! generated code pull in `std`.

use std::path::Path;
use std::process::Command;

#[test]
fn generated_robot_builds_in_a_no_std_crate() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(["build", "--quiet", "--locked", "--manifest-path"])
        .arg(root.join("tests/nostd/Cargo.toml"))
        .arg("--target-dir")
        .arg(root.join("target/no-std"))
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "the no_std crate does not build:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
