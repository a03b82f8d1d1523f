//! The workspace's manifests as `cargo package` and a user's `Cargo.toml` need them: which crates
//! ship, their metadata, licence files and README, the minimum Rust version every member
//! inherits, and versions beside the paths between the shipped crates (a published crate that
//! depends on a sibling by path alone cannot be packaged).

use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The crates a user depends on or installs; everything else only builds or tests them.
const SHIPPED: [&str; 6] = [
    "dyngen-cli",
    "dyngen-codegen",
    "dyngen-control",
    "dyngen-identify",
    "dyngen-model",
    "dyngen-runtime",
];

fn root() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).to_path_buf()
}

fn metadata() -> Value {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(root())
        .args(["metadata", "--no-deps", "--format-version", "1", "--offline"])
        .output()
        .expect("cargo metadata runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("cargo metadata prints JSON")
}

fn text<'a>(package: &'a Value, key: &str) -> &'a str {
    package[key].as_str().unwrap_or("")
}

fn published(package: &Value) -> bool {
    // `publish = false` is an empty list of registries; no key at all means crates.io.
    !matches!(package["publish"].as_array(), Some(registries) if registries.is_empty())
}

fn workspace_version() -> String {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).expect("root manifest");
    let line = manifest
        .lines()
        .skip_while(|l| l.trim() != "[workspace.package]")
        .find(|l| l.starts_with("version"))
        .expect("[workspace.package] has a version");
    line.split('"').nth(1).expect("quoted version").to_string()
}

#[test]
fn exactly_the_shipped_crates_are_published() {
    let meta = metadata();
    let packages = meta["packages"].as_array().expect("packages");
    let shipped: BTreeSet<&str> = packages
        .iter()
        .filter(|p| published(p))
        .map(|p| text(p, "name"))
        .collect();
    assert_eq!(shipped, SHIPPED.into_iter().collect::<BTreeSet<_>>());
    for p in packages.iter().filter(|p| !published(p)) {
        let manifest = text(p, "manifest_path");
        let is_test_only = manifest.contains("/tests/");
        let is_tool = ["/xtask/", "/generated/", "/templates/"]
            .iter()
            .any(|d| manifest.contains(d));
        assert!(
            is_test_only || is_tool,
            "{manifest}: an unpublished crate outside tests/ and the tools"
        );
    }
}

#[test]
fn every_crate_inherits_the_minimum_rust_version() {
    let meta = metadata();
    let root_manifest = std::fs::read_to_string(root().join("Cargo.toml")).expect("root manifest");
    let declared = root_manifest
        .lines()
        .find(|l| l.starts_with("rust-version"))
        .and_then(|l| l.split('"').nth(1))
        .expect("[workspace.package] rust-version");
    for p in meta["packages"].as_array().expect("packages") {
        assert_eq!(
            text(p, "rust_version"),
            declared,
            "{}: rust-version differs from the workspace's",
            text(p, "name")
        );
    }
}

#[test]
fn shipped_crates_have_what_a_registry_needs() {
    let meta = metadata();
    let version = workspace_version();
    let members: BTreeSet<&str> = meta["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .map(|p| text(p, "name"))
        .collect();
    for p in meta["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .filter(|p| published(p))
    {
        let name = text(p, "name");
        let dir = Path::new(text(p, "manifest_path"))
            .parent()
            .expect("crate dir")
            .to_path_buf();
        assert_eq!(text(p, "version"), version, "{name}: version");
        assert_eq!(text(p, "license"), "MIT OR Apache-2.0", "{name}: licence");
        assert!(text(p, "description").len() > 20, "{name}: description");
        for key in ["keywords", "categories"] {
            let list = p[key].as_array().map_or(0, Vec::len);
            assert!(
                (1..=5).contains(&list),
                "{name}: {list} {key}, crates.io takes 1 to 5"
            );
        }
        let readme = text(p, "readme");
        assert!(!readme.is_empty() && dir.join(readme).is_file(), "{name}: README");
        for licence in ["LICENSE-MIT", "LICENSE-APACHE"] {
            let body = std::fs::read_to_string(dir.join(licence)).unwrap_or_default();
            let expected = if licence == "LICENSE-MIT" {
                "Permission is hereby granted"
            } else {
                "Apache License"
            };
            assert!(body.contains(expected), "{name}: {licence}");
        }
        for dep in p["dependencies"].as_array().expect("dependencies") {
            let (dep_name, kind) = (text(dep, "name"), text(dep, "kind"));
            if kind == "dev" || !members.contains(dep_name) {
                continue;
            }
            assert!(
                SHIPPED.contains(&dep_name),
                "{name} depends on {dep_name}, which is not published"
            );
            assert_eq!(
                text(dep, "req"),
                format!("^{version}"),
                "{name} → {dep_name}: a path dependency needs the sibling's version beside it"
            );
        }
    }
}
