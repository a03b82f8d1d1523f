//! Vendor URDFs round quarter turns (`1.5708`): dyngen says so with the place and the size of
//! the change, keeps the value unless the description opts in (`snap_angles`), and with the
//! opt-in generates code as lean as for the exact angles.

use dyngen_codegen::description::{load_urdf_str, load_yaml_str, Choices, FrameSpec};
use dyngen_codegen::internals::generate::trace;
use dyngen_codegen::model::Model;
use std::path::Path;

fn panda_urdf() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/urdf/panda.urdf"))
        .expect("panda.urdf")
}

/// The Panda URDF with every `rpy` number rounded to 4 decimals, as vendor files write them.
fn rounded(urdf: &str) -> String {
    let mut out = String::new();
    let mut rest = urdf;
    while let Some(i) = rest.find("rpy=\"") {
        let (head, tail) = rest.split_at(i + 5);
        out.push_str(head);
        let end = tail.find('"').expect("closing quote");
        let numbers: Vec<String> = tail[..end]
            .split_whitespace()
            .map(|x| format!("{:.4}", x.parse::<f64>().expect("number")))
            .collect();
        out.push_str(&numbers.join(" "));
        rest = &tail[end..];
    }
    out.push_str(rest);
    out
}

fn options(snap: Option<f64>) -> Choices {
    Choices {
        end_effector: Some(FrameSpec::link("panda_hand_tcp")),
        locked_joints: vec![
            ("panda_finger_joint1".into(), 0.0),
            ("panda_finger_joint2".into(), 0.0),
        ],
        gravity: None,
        snap_angles: snap,
        inertia: Default::default(),
        frames: Default::default(),
        floating_base: false,
        joint_parameters: None,
        functions: None,
        contacts: Vec::new(),
        frame_references: Default::default(),
        code_shape: Default::default(),
    }
}

fn operations(model: &Model) -> usize {
    let robot = trace(model);
    robot
        .quantities
        .iter()
        .map(|q| {
            let c = robot.graph.op_counts(&q.outputs);
            c.mul + c.add + c.neg
        })
        .sum()
}

#[test]
fn rounded_quarter_turns_warn_and_snap_only_on_request() {
    let text = rounded(&panda_urdf());
    assert!(text.contains("rpy=\"1.5708 0.0000 0.0000\""));
    let file = Path::new("panda_rounded.urdf");
    let kept = load_urdf_str(&text, file, &options(None)).unwrap_or_else(|e| panic!("{e}"));
    let warned: Vec<&String> = kept.warnings.iter().filter(|w| w.contains("π/2")).collect();
    // 4 × `1.5708` and 2 × `-1.5708` (and 3.1416 = 2·π/2): each named with its place.
    assert!(warned.len() >= 6, "{warned:#?}");
    assert!(
        warned.iter().any(|w| w.starts_with("panda_rounded.urdf:")
            && w.contains("origin roll 1.5708 is 3.7e-6 from 1·π/2")
            && w.contains("`snap_angles: 1e-5`")),
        "{warned:#?}"
    );
    let snapped = load_urdf_str(&text, file, &options(Some(1e-4))).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        snapped.warnings.iter().all(|w| !w.contains("π/2")),
        "{:#?}",
        snapped.warnings
    );
    assert!(snapped
        .notes
        .iter()
        .any(|n| n.contains("snapped to 1·π/2 (a change of 3.7e-6)")));
    let exact = load_urdf_str(&panda_urdf(), Path::new("panda.urdf"), &options(None))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(exact.warnings.is_empty(), "{:#?}", exact.warnings);

    // What it is for: with the snap, the rounded file generates code as lean as the exact one
    // (the remaining rounding, of π/6 and π/4, changes numbers but no structure).
    let (lean, dense, reference) = (
        operations(&snapped.model),
        operations(&kept.model),
        operations(&exact.model),
    );
    println!("operations of all functions: exact {reference}, rounded {dense}, rounded and snapped {lean}");
    assert_eq!(lean, reference, "snapped {lean} vs exact {reference}");
    assert!(
        dense as f64 > 1.2 * reference as f64,
        "rounded {dense} vs exact {reference}"
    );
}

/// `robots/urdf/panda_rounded.urdf` (a committed robot, `robots/panda_rounded.yaml`) is
/// exactly `rounded(panda.urdf)` with a comment after the XML declaration saying so.
#[test]
fn committed_panda_rounded_is_the_rounded_panda() {
    let committed = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../robots/urdf/panda_rounded.urdf"
    ))
    .expect("panda_rounded.urdf");
    let start = committed
        .find("\n<!-- panda_rounded.urdf:")
        .expect("leading comment");
    let end = start + committed[start..].find("-->").expect("end of comment") + 3;
    assert!(
        committed[..start].starts_with("<?xml"),
        "comment after the declaration"
    );
    let without_comment = format!("{}{}", &committed[..start], &committed[end..]);
    assert!(
        without_comment == rounded(&panda_urdf()),
        "panda_rounded.urdf is not rounded(panda.urdf)"
    );
}

#[test]
fn snap_angles_from_yaml_and_its_bad_values() {
    let scratch = dyngen_testkit::scratch::scratch_dir("snap");
    let dir = scratch.path();
    std::fs::write(dir.join("panda_rounded.urdf"), rounded(&panda_urdf())).expect("write");
    let wrapper = |snap: &str| {
        format!(
            "urdf: panda_rounded.urdf\nend_effector: panda_hand_tcp\nlocked_joints: {{ panda_finger_joint1: 0.0, panda_finger_joint2: 0.0 }}\n{snap}"
        )
    };
    let yaml = dir.join("panda.yaml");
    let loaded = load_yaml_str(&wrapper("snap_angles: 1e-4\n"), &yaml).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.notes.iter().any(|n| n.contains("snapped to")));
    for bad in [
        "snap_angles: 0.1\n",
        "snap_angles: -1e-4\n",
        "snap_angles: .nan\n",
    ] {
        let e = load_yaml_str(&wrapper(bad), &yaml).unwrap_err().to_string();
        assert!(
            e.contains("panda.yaml:4:")
                && e.contains("must be a tolerance in radians, above 0 and at most 0.001"),
            "{bad}: {e}"
        );
    }
}

/// The build-script API snaps a bare URDF on request: the rounded Panda then generates code as
/// lean as the exact one (the same operation count in every function; the rounded π/4 and π/6
/// change numbers, not structure), and without the option keeps the dense rotations.
#[test]
fn builder_snaps_a_bare_urdf_and_refuses_a_second_snap_for_yaml() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("near_exact_builder");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    let exact = dir.join("exact.urdf");
    let vendor = dir.join("vendor.urdf");
    std::fs::write(&exact, panda_urdf()).expect("write");
    std::fs::write(&vendor, rounded(&panda_urdf())).expect("write");
    // The operation counts each generated function states in its documentation.
    let counts = |urdf: &Path, snap: Option<f64>| -> Vec<String> {
        let file = dyngen_codegen::Builder::new(urdf)
            .out_dir(&dir)
            .module_name("panda")
            .cargo_directives(false)
            .choices(options(snap))
            .compile()
            .unwrap_or_else(|e| panic!("{e}"));
        let code = std::fs::read_to_string(file).expect("generated");
        code.lines()
            .filter(|l| l.contains("Operations:"))
            .map(str::to_owned)
            .collect()
    };
    let from_exact = counts(&exact, None);
    assert!(from_exact.len() > 10, "{from_exact:#?}");
    assert_eq!(counts(&vendor, Some(1e-4)), from_exact, "snapped vs exact");
    assert_ne!(counts(&vendor, None), from_exact, "unsnapped should stay dense");

    // A YAML description that snaps itself: snapping again from the builder names the key.
    let rounded = concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/panda_rounded.yaml");
    let err = dyngen_codegen::Builder::new(rounded)
        .out_dir(&dir)
        .cargo_directives(false)
        .snap_angles(1e-4)
        .compile()
        .expect_err("snap_angles chosen twice");
    assert!(
        err.to_string().contains(
            "`snap_angles` was chosen twice, by `snap_angles:` in the description and by the caller"
        ),
        "{err}"
    );
}

/// A near-exact description (xarm7 as its vendor writes it, quarter turns as `1.5708`) has real
/// folding coefficients of 10⁻¹¹ (its axes are 3.7·10⁻⁶ rad off perpendicular) but no rounding
/// noise in its base parameters: it folds into not many more terms than the snapped description,
/// and its full regressors, rebuilt from the base columns, cost a small multiple of the snapped
/// ones rather than a sum over every base column.
#[test]
fn near_exact_base_parameters_carry_no_rounding_noise() {
    use dyngen_codegen::base_parameters::BaseParameterSet;
    use dyngen_codegen::description::load_with;
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/example-robot-data/xarm_description/xarm7.urdf"
    ));
    let load = |snap: Option<f64>| {
        let options = Choices {
            snap_angles: snap,
            ..Choices::default()
        };
        load_with(path, &options).unwrap_or_else(|e| panic!("{e}")).model
    };
    let (written, snapped) = (load(None), load(Some(1e-4)));
    let terms = |model: &Model| -> (usize, usize) {
        let base = BaseParameterSet::compute(model);
        let all: Vec<f64> = base.terms.iter().flatten().map(|&(_, c)| c.abs()).collect();
        (all.len(), all.iter().filter(|&&c| c < 1e-9).count())
    };
    let ((written_terms, written_tiny), (snapped_terms, snapped_tiny)) = (terms(&written), terms(&snapped));
    println!("folding terms: as written {written_terms} ({written_tiny} below 1e-9), snapped {snapped_terms} ({snapped_tiny})");
    // The small coefficients as written are powers of the 3.7e-6 misalignment (1.35e-11 its
    // square, …); with the rounding noise of the least squares kept there were 611 terms, 459
    // of them below 1e-9.
    assert_eq!(snapped_tiny, 0);
    assert!(
        written_terms < 2 * snapped_terms,
        "{written_terms} folding terms as written against {snapped_terms} snapped"
    );
    let cost = |model: &Model, name: &str| {
        let robot = trace(model);
        let q = robot
            .quantities
            .iter()
            .find(|q| q.name() == name)
            .expect("traced");
        robot.graph.op_counts(&q.outputs).mul
    };
    for name in ["regressor", "torque_regressor"] {
        let (w, s) = (cost(&written, name), cost(&snapped, name));
        println!("{name}: {w} multiplications as written, {s} snapped");
        assert!((w as f64) < 2.5 * s as f64, "{name}: {w} vs {s}");
    }
}
