//! `--inertia as-written|repair|strict`: what every command that loads a bare URDF does with a
//! link whose inertia no real body has (`codegen/tests/data/non-physical/`).

use crate::common;

use common::{arg, dyngen, repository_file};

const NEGATIVE_MOMENT: &str = "codegen/tests/data/non-physical/negative-moment.urdf";
const GROSS: &str = "codegen/tests/data/non-physical/gross.urdf";

fn lines_starting<'a>(stderr: &'a str, start: &str) -> Vec<&'a str> {
    stderr.lines().filter(|l| l.starts_with(start)).collect()
}

#[test]
fn check_warns_by_default_repairs_or_refuses_as_asked() {
    let file = repository_file(NEGATIVE_MOMENT);
    let place = format!(
        "{}:16:7: link 'lower': inertia is not physical: principal moment -1e-4",
        file.display()
    );

    let default = dyngen(&["check", arg(&file)]);
    assert_eq!(default.code, Some(0), "{}", default.output());
    let warnings = lines_starting(&default.stderr, "warning: ");
    assert_eq!(warnings.len(), 1, "{}", default.output());
    assert!(
        warnings[0].starts_with(&format!("warning: {place}")),
        "{}",
        default.output()
    );
    // The same with the default spelled out; --deny-warnings makes it a failure.
    let spelled = dyngen(&["check", arg(&file), "--inertia", "as-written", "--deny-warnings"]);
    assert_eq!(spelled.code, Some(1), "{}", spelled.output());

    let repaired = dyngen(&["check", arg(&file), "--inertia", "repair", "--deny-warnings"]);
    assert_eq!(repaired.code, Some(0), "{}", repaired.output());
    let notes = lines_starting(&repaired.stderr, "note: ");
    assert!(
        notes.iter().any(|n| n.starts_with(&format!("note: {place}"))
            && n.contains("repaired to the nearest physical inertia")),
        "{}",
        repaired.output()
    );

    let strict = dyngen(&["check", arg(&file), "--inertia=strict"]);
    assert_eq!(strict.code, Some(1), "{}", strict.output());
    assert_eq!(
        strict.stderr.lines().count(),
        1,
        "one error line: {}",
        strict.output()
    );
    assert!(
        strict.stderr.starts_with(&format!("error: {place}"))
            && strict.stderr.contains("`inertia: strict` refuses it"),
        "{}",
        strict.output()
    );
}

#[test]
fn a_gross_defect_needs_the_repair_on_every_command() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = repository_file(GROSS);
    let refused = dyngen(&["urdf", arg(&file)]);
    assert_eq!(refused.code, Some(1), "{}", refused.output());
    assert!(
        refused.stderr.contains("give `inertia: repair`"),
        "{}",
        refused.output()
    );

    // Repaired, the export is a physical robot that loads back in the default mode, silently.
    let exported = dir.path().join("gross.urdf");
    let export = dyngen(&["urdf", arg(&file), "--inertia", "repair", "-o", arg(&exported)]);
    assert_eq!(export.code, Some(0), "{}", export.output());
    let back = dyngen(&["check", arg(&exported), "--inertia", "strict", "--deny-warnings"]);
    assert_eq!(back.code, Some(0), "{}", back.output());

    let trajectory = dir.path().join("excitation.csv");
    for args in [
        vec!["info", arg(&file), "--inertia", "repair"],
        vec![
            "excite",
            arg(&file),
            "-o",
            arg(&trajectory),
            "--duration",
            "2",
            "--rate",
            "50",
            "--iterations",
            "2",
            "--inertia",
            "repair",
        ],
    ] {
        let run = dyngen(&args);
        assert_eq!(run.code, Some(0), "{args:?}: {}", run.output());
        let refused = dyngen(&args[..args.len() - 2]);
        assert_eq!(
            refused.code,
            Some(1),
            "{args:?} without the repair: {}",
            refused.output()
        );
    }
}

#[test]
fn the_flag_takes_three_values_and_is_refused_where_the_yaml_chooses() {
    let file = repository_file(NEGATIVE_MOMENT);
    let bad = dyngen(&["check", arg(&file), "--inertia", "repaired"]);
    assert_eq!(bad.code, Some(2), "{}", bad.output());
    assert!(
        bad.stderr.contains("possible values: as-written, repair, strict"),
        "{}",
        bad.output()
    );

    // A YAML description that leaves `inertia:` to the caller takes the flag; one that
    // writes it refuses the flag, naming the key.
    let yaml = repository_file("codegen/tests/data/non-physical/triangle-inequality.yaml");
    let repaired = dyngen(&["check", arg(&yaml), "--inertia", "repair"]);
    assert_eq!(repaired.code, Some(0), "{}", repaired.output());
    assert!(
        repaired
            .stderr
            .contains("repaired to the nearest physical inertia"),
        "{}",
        repaired.output()
    );
    let yaml = repository_file("codegen/tests/data/non-physical/gross-repaired.yaml");
    let refused = dyngen(&["check", arg(&yaml), "--inertia", "strict"]);
    assert_eq!(refused.code, Some(1), "{}", refused.output());
    assert!(
        refused
            .stderr
            .contains("`inertia` was chosen twice, by `inertia:` in the description and by the caller"),
        "{}",
        refused.output()
    );
}
