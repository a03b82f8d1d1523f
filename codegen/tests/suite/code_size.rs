//! The estimate of a module's size that decides whether dyngen generates a robot: close to the
//! bytes written (the committed modules, and robots generated here), and a guard that refuses
//! what would not finish, at once, while a 100-joint mobile manipulator passes.

use dyngen_codegen::description::{load, load_with, Choices, FrameReferences, FrameSelection};
use dyngen_codegen::generate::{
    estimate_code_size, frame_references, generate_robot, generate_robot_with, MAX_GENERATED_BYTES,
};
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
    let (references, _) = frame_references(model, functions, choice);
    estimate_code_size(model, functions, references).total()
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
        let estimated = estimate(&loaded.model, functions, loaded.choices.frame_references);
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
/// Dual has 101; its module is 12 MB) passes, a chain of 150 does not.
#[test]
fn the_guard_follows_the_shape_not_the_joint_count() {
    let dir = tempfile::tempdir().expect("dir");
    let (_, hands) = load_text(dir.path(), "hands.yaml", &two_arms_with_hands(11, 4));
    assert_eq!(hands.dof(), 105);
    let bytes = estimate(&hands, default_functions(&hands), FrameReferences::Auto);
    assert!(bytes < MAX_GENERATED_BYTES / 2, "{bytes}");

    let (path, long) = load_text(dir.path(), "long.yaml", &chain(150));
    assert!(estimate(&long, default_functions(&long), FrameReferences::Auto) > MAX_GENERATED_BYTES);
    let start = Instant::now();
    let e = generate_robot(&path, "long.yaml", "Long", "test")
        .expect_err("too large")
        .to_string();
    assert!(start.elapsed() < Duration::from_secs(5), "not at once");
    for expected in [
        "long.yaml",
        "150 moving joints",
        "MB of Rust",
        "`forward_dynamics` about",
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
