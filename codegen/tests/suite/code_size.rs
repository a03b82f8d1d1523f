//! The estimate of a module's size that decides whether dyngen generates a robot: close to the
//! bytes written (the committed modules, and robots generated here), and a guard that refuses
//! what would not finish, at once, while a 100-joint mobile manipulator passes.

use dyngen_codegen::description::{load, load_with, Choices, CodeShape, FrameReferences, FrameSelection};
use dyngen_codegen::generate::{
    composed_functions, estimate_code_size, frame_references, generate_robot, generate_robot_with, Shapes,
    MAX_GENERATED_BYTES,
};
use dyngen_codegen::internals::generate::QuantityKind;
use dyngen_codegen::model::Model;
use dyngen_codegen::{FunctionGroup, Functions};
use dyngen_testkit::workspace_root;
use std::path::Path;
use std::time::{Duration, Instant};

/// The groups a description that chooses none is generated with.
fn default_functions(model: &Model) -> Functions {
    let functions = Functions::default_for(model.dof());
    match model.contacts().is_empty() {
        true => functions.without(FunctionGroup::Contacts),
        false => functions,
    }
}

/// The estimated bytes of `model`'s module with `functions`, its frames in the reference frames
/// `choice` writes.
fn estimate(model: &Model, functions: Functions, choice: FrameReferences) -> usize {
    let (frame_references, _) = frame_references(model, functions, choice);
    let shapes = Shapes {
        frame_references,
        ..Shapes::flat()
    };
    estimate_code_size(model, functions, &shapes).total()
}

fn assert_within_two(what: &str, estimated: usize, written: usize) {
    let ratio = estimated as f64 / written as f64;
    assert!(
        (0.5..=2.0).contains(&ratio),
        "{what}: estimated {estimated} bytes, written {written} ({ratio:.2}×)"
    );
}

#[test]
fn the_estimate_is_within_two_of_every_committed_module() {
    let robots = workspace_root().join("robots");
    let mut checked = 0;
    for entry in std::fs::read_dir(&robots).expect("robots/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("yaml") {
            continue;
        }
        let loaded = load(&path).unwrap_or_else(|e| panic!("{e}"));
        let functions = loaded
            .choices
            .functions
            .unwrap_or_else(|| default_functions(&loaded.model));
        let stem = path.file_stem().and_then(|s| s.to_str()).expect("a stem");
        let module = workspace_root().join("generated/src").join(format!("{stem}.rs"));
        let written = std::fs::metadata(&module)
            .unwrap_or_else(|e| panic!("{}: {e}", module.display()))
            .len();
        let (shapes, _) = dyngen_codegen::generate::shapes(&loaded.model, functions, &loaded.choices);
        let estimated = estimate_code_size(&loaded.model, functions, &shapes).total();
        assert_within_two(stem, estimated, written as usize);
        checked += 1;
    }
    assert!(checked >= 8, "only {checked} robots");
}

/// A chain of `n` joints, the deepest tree of its size.
fn chain(n: usize) -> String {
    let mut text = String::from("name: chain\nlinks:\n  - name: l0\n");
    for i in 1..=n {
        text += &format!(
            "  - name: l{i}\n    inertial: {{ mass: 1.0, origin: {{ xyz: [0.05, 0, 0.1] }}, \
             inertia: {{ ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.012, iyz: 0, izz: 0.008 }} }}\n"
        );
    }
    text += "joints:\n";
    for i in 1..=n {
        let axis = if i % 2 == 0 { "[0, 1, 0]" } else { "[0, 0, 1]" };
        text += &format!(
            "  - {{ name: j{i}, type: revolute, parent: l{}, child: l{i}, origin: {{ xyz: [0, 0, 0.2] }}, \
             axis: {axis}, limit: {{ lower: -3, upper: 3, velocity: 2, effort: 100 }} }}\n",
            i - 1
        );
    }
    text
}

/// A mobile manipulator shaped as TIAGo Dual: a torso joint and a head, two 7-joint arms, each
/// with a hand of `fingers` fingers of `phalanges` joints (`3 + 2 (7 + fingers · phalanges)`
/// joints).
fn two_arms_with_hands(fingers: usize, phalanges: usize) -> String {
    let mut links = vec!["base".to_owned()];
    let mut joints = Vec::new();
    let joint = |parent: &str,
                 child: String,
                 axis: &str,
                 joints: &mut Vec<String>,
                 links: &mut Vec<String>| {
        joints.push(format!(
            "  - {{ name: {child}_joint, type: revolute, parent: {parent}, child: {child}, \
             origin: {{ xyz: [0.02, 0.01, 0.1] }}, axis: {axis}, limit: {{ lower: -2, upper: 2, velocity: 2, effort: 50 }} }}"
        ));
        links.push(child);
    };
    joint("base", "torso".into(), "[0, 0, 1]", &mut joints, &mut links);
    joint("torso", "head_1".into(), "[0, 0, 1]", &mut joints, &mut links);
    joint("head_1", "head_2".into(), "[0, 1, 0]", &mut joints, &mut links);
    for side in ["left", "right"] {
        let mut parent = "torso".to_owned();
        for k in 1..=7 {
            let child = format!("{side}_arm_{k}");
            let axis = if k % 2 == 0 { "[0, 1, 0]" } else { "[0, 0, 1]" };
            joint(&parent, child.clone(), axis, &mut joints, &mut links);
            parent = child;
        }
        for finger in 1..=fingers {
            let mut at = parent.clone();
            for p in 1..=phalanges {
                let child = format!("{side}_finger_{finger}_{p}");
                joint(&at, child.clone(), "[1, 0, 0]", &mut joints, &mut links);
                at = child;
            }
        }
    }
    let links: Vec<String> = (links.iter())
        .map(|l| {
            format!(
                "  - {{ name: {l}, inertial: {{ mass: 0.5, origin: {{ xyz: [0, 0, 0.05] }}, \
                 inertia: {{ ixx: 0.001, ixy: 0, ixz: 0, iyy: 0.001, iyz: 0, izz: 0.001 }} }} }}"
            )
        })
        .collect();
    format!(
        "name: two_arms\nlinks:\n{}\njoints:\n{}\n",
        links.join("\n"),
        joints.join("\n")
    )
}

fn load_text(dir: &Path, name: &str, text: &str) -> (std::path::PathBuf, Model) {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    let model = load(&path).unwrap_or_else(|e| panic!("{e}")).model;
    (path, model)
}

#[test]
fn the_estimate_is_within_two_of_modules_generated_here() {
    let dir = tempfile::tempdir().expect("dir");
    let all = Functions::all().without(FunctionGroup::Contacts);
    for (name, text, functions) in [
        ("chain.yaml", chain(16), None),
        ("chain_all.yaml", chain(9) + "functions: all\n", Some(all)),
        ("hands.yaml", two_arms_with_hands(2, 2), None),
    ] {
        let (path, model) = load_text(dir.path(), name, &text);
        let functions = functions.unwrap_or_else(|| default_functions(&model));
        let robot = generate_robot(&path, name, "Robot", "test").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(robot.functions, functions, "{name}");
        let estimated = estimate(&model, functions, FrameReferences::Auto);
        assert_within_two(name, estimated, robot.code.len());
    }
}

/// What grows without bound is refused at once, naming the size and the largest group; the
/// shape, not the joint count, decides: a mobile manipulator of more than 100 joints (TIAGo
/// Dual has 101; its module is 7 MB, its `D⁻¹` composed) passes, a chain of 250 does not (its
/// `D` alone would be about 100 MB; a chain of 150 now generates, `D⁻¹` and forward dynamics
/// composed).
#[test]
fn the_guard_follows_the_shape_not_the_joint_count() {
    let dir = tempfile::tempdir().expect("dir");
    let (_, hands) = load_text(dir.path(), "hands.yaml", &two_arms_with_hands(11, 4));
    assert_eq!(hands.dof(), 105);
    let bytes = estimate(&hands, default_functions(&hands), FrameReferences::Auto);
    assert!(bytes < MAX_GENERATED_BYTES / 2, "{bytes}");

    let (path, long) = load_text(dir.path(), "long.yaml", &chain(250));
    let functions = default_functions(&long);
    let (shapes, _) = dyngen_codegen::generate::shapes(&long, functions, &Choices::default());
    assert!(estimate_code_size(&long, functions, &shapes).total() > MAX_GENERATED_BYTES);
    let start = Instant::now();
    let e = generate_robot(&path, "long.yaml", "Long", "test")
        .expect_err("too large")
        .to_string();
    assert!(start.elapsed() < Duration::from_secs(5), "not at once");
    for expected in [
        "long.yaml",
        "250 moving joints",
        "MB of Rust",
        "`dynamics` about",
        "lock joints",
    ] {
        assert!(e.contains(expected), "{expected:?} missing from: {e}");
    }
}

/// `frame_references: auto` writes every reference frame while the frames' code is small (an
/// arm with every link a frame, a humanoid's feet) and base axes alone where it would dominate
/// the module (every link of a humanoid), with a note; a choice made stands. The module then
/// has no `local` or `world` function of its own and is far smaller, as estimated.
#[test]
fn frame_references_follow_the_size_of_the_frames_code() {
    let g1 =
        workspace_root().join("codegen/tests/data/example-robot-data/g1_description/g1_29dof_rev_1_0.urdf");
    let humanoid = |frames: FrameSelection, frame_references: FrameReferences| Choices {
        floating_base: true,
        frames,
        frame_references,
        ..Choices::default()
    };
    let resolved = |choices: &Choices| {
        let model = load_with(&g1, choices).unwrap_or_else(|e| panic!("{e}")).model;
        frame_references(&model, default_functions(&model), choices.frame_references).0
    };
    let every_link = humanoid(FrameSelection::AllLinks, FrameReferences::Auto);
    assert_eq!(resolved(&every_link), FrameReferences::Aligned);
    assert_eq!(
        resolved(&humanoid(FrameSelection::EndEffector, FrameReferences::Auto)),
        FrameReferences::All
    );
    assert_eq!(
        resolved(&humanoid(FrameSelection::AllLinks, FrameReferences::All)),
        FrameReferences::All
    );
    let panda = load(&workspace_root().join("robots/panda.yaml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(panda.choices.frames, FrameSelection::AllLinks);
    let functions = panda
        .choices
        .functions
        .unwrap_or_else(|| default_functions(&panda.model));
    assert_eq!(
        frame_references(&panda.model, functions, FrameReferences::Auto).0,
        FrameReferences::All
    );

    let robot =
        generate_robot_with(&g1, "g1.urdf", "G1", "test", &every_link).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        robot
            .notes
            .iter()
            .any(|n| n.contains("converted from `local_world_aligned` at run time")),
        "{:?}",
        robot.notes
    );
    for written in [
        "fn frame_jacobian_pelvis_local_world_aligned(",
        "fn frame_jacobian_time_variation_pelvis_local_world_aligned(",
        "fn frame_velocity_pelvis_local_world_aligned(",
    ] {
        assert!(robot.code.contains(written), "{written}");
    }
    for converted in ["_local(", "_world("] {
        assert!(!robot.code.contains(converted), "{converted}");
    }
    let model = load_with(&g1, &every_link).unwrap().model;
    let all = estimate(&model, robot.functions, FrameReferences::All);
    // The frames are about three quarters of that estimate; in base axes alone they are a third
    // of themselves.
    assert!(
        robot.code.len() * 5 < all * 3,
        "{} bytes written, {all} estimated in every reference frame",
        robot.code.len()
    );
    assert_within_two(
        "G1, every link",
        estimate(&model, robot.functions, FrameReferences::Aligned),
        robot.code.len(),
    );
}

/// `code_shape: auto` composes the derivatives of forward dynamics where their straight-line
/// code would be megabytes (two arms with hands), not on a humanoid, a quadruped or an arm;
/// `flat` and `composed` are taken as chosen; a composed function is a call, and the module
/// shrinks by about the function's estimate.
#[test]
fn the_code_shape_follows_the_size_of_a_function() {
    let derivatives = Functions::from_keywords(["derivatives"]).expect("a group");
    let data = workspace_root().join("codegen/tests/data/example-robot-data");
    let g1 = data.join("g1_description/g1_29dof_rev_1_0.urdf");
    let floating = |path: &Path| {
        let choices = Choices {
            floating_base: true,
            ..Choices::default()
        };
        load_with(path, &choices).unwrap_or_else(|e| panic!("{e}")).model
    };
    let humanoid = floating(&g1);
    let composed = |model: &Model, choice: CodeShape| -> Vec<QuantityKind> {
        let kinds = composed_functions(model, derivatives, choice);
        kinds.into_iter().map(|(kind, _)| kind).collect()
    };
    let fdd = QuantityKind::ForwardDynamicsDerivatives;
    assert_eq!(composed(&humanoid, CodeShape::Auto), []);
    assert_eq!(composed(&humanoid, CodeShape::Composed), [fdd]);
    let solo = floating(&workspace_root().join("robots/urdf/solo12.urdf"));
    assert_eq!(composed(&solo, CodeShape::Auto), []);
    let panda = load(&workspace_root().join("robots/panda.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(composed(&panda, CodeShape::Auto), []);
    let dir = tempfile::tempdir().expect("dir");
    let (_, hands) = load_text(dir.path(), "hands.yaml", &two_arms_with_hands(5, 3));
    assert_eq!(hands.dof(), 47);
    assert_eq!(composed(&hands, CodeShape::Auto), [fdd]);
    assert_eq!(composed(&hands, CodeShape::Flat), []);
    let choices = Choices {
        functions: Some(derivatives),
        ..Choices::default()
    };
    let (shapes, notes) = dyngen_codegen::generate::shapes(&hands, derivatives, &choices);
    assert_eq!(shapes.composed, [fdd]);
    let note = "`forward_dynamics_derivatives` as straight-line code would be about";
    assert!(notes.iter().any(|n| n.contains(note)), "{notes:?}");
    // With the default groups of a large robot, its `D⁻¹` (two arms with many fingers).
    let (_, many_fingers) = load_text(dir.path(), "fingers.yaml", &two_arms_with_hands(11, 4));
    let functions = default_functions(&many_fingers);
    let kinds: Vec<QuantityKind> = composed_functions(&many_fingers, functions, CodeShape::Auto)
        .into_iter()
        .map(|(kind, _)| kind)
        .collect();
    assert!(kinds.contains(&QuantityKind::MassMatrixInverse), "{kinds:?}");
    // Without the group, nothing to compose.
    let default = Functions::from_keywords([]).expect("no group");
    assert_eq!(composed_functions(&hands, default, CodeShape::Composed), []);

    let choose = |code_shape: CodeShape| Choices {
        floating_base: true,
        functions: Some(derivatives),
        code_shape,
        ..Choices::default()
    };
    let flat = generate_robot_with(&g1, "g1.urdf", "G1", "test", &choose(CodeShape::Auto))
        .unwrap_or_else(|e| panic!("{e}"));
    let chosen = generate_robot_with(&g1, "g1.urdf", "G1", "test", &choose(CodeShape::Composed))
        .unwrap_or_else(|e| panic!("{e}"));
    // A chosen shape needs no note.
    assert!(
        !chosen.notes.iter().any(|n| n.contains(note)),
        "{:?}",
        chosen.notes
    );
    assert!(flat.code.contains("fn forward_dynamics_derivatives_part0("));
    assert!(!chosen.code.contains("fn forward_dynamics_derivatives_part0("));
    assert!(chosen
        .code
        .contains("__private::composed::forward_dynamics_derivatives("));
    // The base's six coordinates a chain above the first joints, in the tree the call declares.
    let compact: String = chosen.code.split_whitespace().collect();
    assert!(compact.contains("Tree::new([None,Some(0),Some(1),Some(2),Some(3),Some(4),Some(5),"));
    let saved = flat.code.len() - chosen.code.len();
    let (_, estimated) = composed_functions(&humanoid, derivatives, CodeShape::Composed)[0];
    assert_within_two("G1's ∂ν̇/∂x", estimated, saved);
    let (shapes, _) = dyngen_codegen::generate::shapes(&humanoid, derivatives, &choose(CodeShape::Composed));
    assert_within_two(
        "G1, derivatives composed",
        estimate_code_size(&humanoid, derivatives, &shapes).total(),
        chosen.code.len(),
    );
}
