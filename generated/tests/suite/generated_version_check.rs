//! Every committed generated module starts by checking that it is compiled against the runtime
//! of the release that generated it, so a version mismatch is one compile error that names both
//! versions instead of errors about the runtime's hidden paths.

use std::path::Path;

#[test]
fn every_generated_module_requires_the_runtime_it_was_generated_for() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/src"));
    let check = format!(
        "\ndyngen_runtime::__require_version!({:?});\n",
        dyngen_runtime::__require_version!()
    );
    let mut modules = 0;
    for entry in std::fs::read_dir(dir).expect("generated/src") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "rs") && path.file_name() != Some("lib.rs".as_ref()) {
            modules += 1;
            let code = std::fs::read_to_string(&path).expect("readable");
            let first_item = code.lines().find(|l| !l.is_empty() && !l.starts_with("//"));
            assert_eq!(
                first_item,
                Some(check.trim()),
                "{}: the first item is not the version check",
                path.display()
            );
            assert_eq!(code.matches(&check).count(), 1, "{}", path.display());
        }
    }
    assert!(modules >= 3, "found the generated robots");
}
