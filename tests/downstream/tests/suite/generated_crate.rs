//! Through the library, as a user's tool would: `Builder` writes the 2-DOF vendor URDF into a
//! fresh crate of its own (`src/robot.rs`, depending on nothing but `dyngen-runtime`), whose
//! test compares the compiled functions with values computed here by `NumericDynamics`; then
//! `cargo test --offline` runs that crate.

use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::Builder;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

pub(super) fn workspace_root() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .canonicalize()
        .expect("workspace root")
}

/// A Rust array literal whose numbers read back as the same `f64`s.
fn array(values: impl IntoIterator<Item = f64>) -> String {
    let items: Vec<String> = values.into_iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", items.join(", "))
}

/// States away from any symmetry: every term of the dynamics is non-zero.
const STATES: [([f64; 2], [f64; 2], [f64; 2]); 3] = [
    ([0.3, -0.7], [0.5, 1.1], [-0.4, 0.9]),
    ([1.2, 0.4], [-1.3, 0.2], [0.8, -0.6]),
    ([-0.9, 2.1], [0.7, -0.9], [1.5, 0.3]),
];

/// The test of the temporary crate: the generated functions against the expected values.
fn comparison_test(model: &dyngen_codegen::model::Model) -> String {
    let dynamics = NumericDynamics::new(model);
    let mut cases = String::new();
    for (q, qd, qdd) in STATES {
        let tau = dynamics.inverse_dynamics(&q, &qd, &qdd);
        let g = dynamics.gravity_torque(&q);
        let d = dynamics.mass_matrix(&q);
        let (_, position) = dynamics.end_effector_pose(&q);
        let _ = writeln!(
            cases,
            "    check({}, {}, {}, {}, {}, {}, {});",
            array(q),
            array(qd),
            array(qdd),
            array(tau.iter().copied()),
            array(g.iter().copied()),
            // Row by row: `D[i][j]`.
            array(
                (0..2)
                    .flat_map(|i| (0..2).map(move |j| (i, j)))
                    .map(|(i, j)| d[(i, j)])
            ),
            array(position.iter().copied()),
        );
    }
    format!(
        r#"//! Written by `generated_crate.rs` of dyngen's downstream tests: the generated robot
//! against `NumericDynamics`' values for the same description.

use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::prelude::*;
use generated_two_dof::robot::Robot;

fn close(what: &str, got: f64, want: f64) {{
    assert!((got - want).abs() <= 1e-9 * (1.0 + want.abs()), "{{what}}: generated {{got}}, expected {{want}}");
}}

#[allow(clippy::too_many_arguments)]
fn check(q: [f64; 2], qd: [f64; 2], qdd: [f64; 2], tau: [f64; 2], g: [f64; 2], d: [f64; 4], p: [f64; 3]) {{
    let t = JointTrig::new(&SVector::from(q));
    let got = Robot::inverse_dynamics(&t, &SVector::from(qd), &SVector::from(qdd));
    let gravity = Robot::gravity(&t);
    let mass = Robot::mass_matrix(&t);
    let pose = Robot::forward_kinematics(&t);
    for i in 0..2 {{
        close("tau", got[i], tau[i]);
        close("g", gravity[i], g[i]);
        for j in 0..2 {{
            close("D", mass[(i, j)], d[2 * i + j]);
        }}
    }}
    for i in 0..3 {{
        close("end-effector position", pose.translation[i], p[i]);
    }}
}}

#[test]
fn generated_functions_match_the_generic_dynamics() {{
{cases}}}
"#
    )
}

/// A fresh crate `name` in `krate` around the modules `src/<module>.rs` (already written),
/// depending on nothing but `dyngen-runtime`, with `#![deny(warnings)]`.
pub(super) fn write_crate(krate: &Path, name: &str, modules: &[&str]) {
    let root = workspace_root();
    let manifest = format!(
        "[package]\nname = \"{name}\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n\
         [dependencies]\ndyngen-runtime = {{ path = {:?} }}\n\n\
         # Not a member of any workspace above the temporary directory.\n[workspace]\n",
        root.join("runtime").display().to_string()
    );
    std::fs::write(krate.join("Cargo.toml"), manifest).expect("Cargo.toml");
    // The workspace's versions of nalgebra and the rest, already in the local registry cache:
    // an offline build needs nothing new.
    std::fs::copy(root.join("Cargo.lock"), krate.join("Cargo.lock")).expect("Cargo.lock");
    let modules: String = modules.iter().map(|m| format!("pub mod {m};\n")).collect();
    std::fs::write(
        krate.join("src/lib.rs"),
        format!("#![deny(warnings)]\n\n{modules}"),
    )
    .expect("lib.rs");
}

/// `cargo <args> --offline` in the crate at `krate`: (success, stdout, stderr).
pub(super) fn cargo(krate: &Path, args: &[&str]) -> (bool, String, String) {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(args)
        .args(["--offline", "--manifest-path"])
        .arg(krate.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(workspace_root().join("target/generated-crate"))
        .output()
        .expect("cargo runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_crate_generated_through_the_builder_compiles_and_matches() {
    let root = workspace_root();
    let description = root.join("codegen/tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf");
    let model = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(model.dof(), 2);

    let dir = tempfile::tempdir().expect("temp dir");
    let krate = dir.path();
    std::fs::create_dir_all(krate.join("src")).expect("src");
    std::fs::create_dir_all(krate.join("tests")).expect("tests");
    let written = Builder::new(&description)
        .output_file(krate.join("src/robot.rs"))
        .cargo_directives(false)
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(written, krate.join("src/robot.rs"));
    write_crate(krate, "generated-two-dof", &["robot"]);
    std::fs::write(krate.join("tests/values.rs"), comparison_test(&model)).expect("test");

    let (success, stdout, stderr) = cargo(krate, &["test"]);
    assert!(success, "the generated crate's test fails:\n{stdout}\n{stderr}");
    assert!(
        stdout.contains("test generated_functions_match_the_generic_dynamics ... ok"),
        "the comparison ran:\n{stdout}"
    );
}

/// A robot generated with kinematics and dynamics only compiles without a warning, and code that
/// calls a function of a group it lacks fails to compile with a message that names the group
/// and says how to generate it.
#[test]
fn a_missing_group_is_a_compile_error_that_says_how_to_generate_it() {
    let call = "fn accelerations<R: ForwardDynamics<2, 20>>() -> SVector<f64, 2> {\n    \
                let t = JointTrig::new(&SVector::zeros());\n    \
                R::forward_dynamics(&t, &SVector::zeros(), &SVector::zeros())\n}\n";
    let absent = [
        "impl Regressors",
        "impl ForwardDynamics",
        "impl DynamicsDerivatives",
        "impl BaseParameters",
    ];
    only_kinematics_and_dynamics(false, &absent, call);
}

/// On a floating base too: the groups mean the same, each its floating trait.
#[test]
fn a_floating_base_gets_only_the_groups_it_chose() {
    let call = "fn accelerations<R: FloatingForwardDynamics<2, 8, 30>>() -> SVector<f64, 8> {\n    \
                let mut q = [0.0; 9];\n    q[6] = 1.0;\n    \
                let t = FloatingTrig::from_configuration(&q).unwrap();\n    \
                R::forward_dynamics(&t, &SVector::zeros(), &SVector::zeros())\n}\n";
    let absent = [
        "impl FloatingRegressors",
        "impl FloatingForwardDynamics",
        "impl FloatingDynamicsDerivatives",
        "impl FloatingBaseParameters",
        "impl FloatingFrameKinematics",
    ];
    only_kinematics_and_dynamics(true, &absent, call);
}

/// The 2-DOF arm generated with kinematics and dynamics only (on a floating base if
/// `floating`) has none of the implementations `absent`, builds without a warning, and
/// `accelerations`, which calls forward dynamics, fails to build with a message that names the
/// group and how to add it.
fn only_kinematics_and_dynamics(floating: bool, absent: &[&str], accelerations: &str) {
    let root = workspace_root();
    let description = root.join("codegen/tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf");
    let dir = tempfile::tempdir().expect("temp dir");
    let krate = dir.path();
    std::fs::create_dir_all(krate.join("src")).expect("src");
    std::fs::create_dir_all(krate.join("examples")).expect("examples");
    let builder = Builder::new(&description)
        .output_file(krate.join("src/robot.rs"))
        .cargo_directives(false)
        .functions(&[]);
    let builder = match floating {
        true => builder.floating_base(),
        false => builder,
    };
    builder.compile().unwrap_or_else(|e| panic!("{e}"));
    let code = std::fs::read_to_string(krate.join("src/robot.rs")).expect("generated");
    for absent in absent {
        assert!(!code.contains(absent), "{absent} generated without being chosen");
    }
    let name = match floating {
        true => "generated-two-dof-floating-dynamics-only",
        false => "generated-two-dof-dynamics-only",
    };
    write_crate(krate, name, &["robot"]);
    let (success, _, stderr) = cargo(krate, &["build", "--lib"]);
    assert!(
        success,
        "kinematics and dynamics alone do not build cleanly:\n{stderr}"
    );

    let library = name.replace('-', "_");
    std::fs::write(
        krate.join("examples/needs_forward_dynamics.rs"),
        format!(
            "use dyngen_runtime::nalgebra::SVector;\nuse dyngen_runtime::prelude::*;\n\
             use {library}::robot::Robot;\n\n{accelerations}\n\
             fn main() {{\n    println!(\"{{}}\", accelerations::<Robot>());\n}}\n"
        ),
    )
    .expect("example");
    let (success, _, stderr) = cargo(krate, &["build", "--example", "needs_forward_dynamics"]);
    assert!(
        !success,
        "forward dynamics called on a robot generated without them"
    );
    for expected in [
        "`Robot` was generated without the group `forward_dynamics`",
        "add `forward_dynamics` to `functions:`",
    ] {
        assert!(
            stderr.contains(expected),
            "the error does not say {expected:?}:\n{stderr}"
        );
    }
}

/// Frames whose names Rust spells alike (`link_1` and `Link1`, as ROS-Industrial URDFs have
/// them) get told-apart identifiers, and the generated crate compiles without a warning.
#[test]
fn frames_spelled_alike_compile_with_their_suffixes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let krate = dir.path();
    std::fs::create_dir_all(krate.join("src")).expect("src");
    let urdf = krate.join("twins.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="twins">
  <link name="base_link"/>
  <link name="link_1"><inertial><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="Link1"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="a-b"/>
  <link name="a_b"/>
  <joint name="joint_a1" type="revolute"><parent link="base_link"/><child link="link_1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="100" velocity="2"/></joint>
  <joint name="joint_a2" type="revolute"><parent link="link_1"/><child link="Link1"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="100" velocity="2"/></joint>
  <joint name="to_ab" type="fixed"><parent link="Link1"/><child link="a-b"/><origin xyz="0.4 0 0"/></joint>
  <joint name="to_a_b" type="fixed"><parent link="Link1"/><child link="a_b"/><origin xyz="0.5 0 0"/></joint>
</robot>
"#,
    )
    .expect("urdf");
    let report = Builder::new(&urdf)
        .output_file(krate.join("src/robot.rs"))
        .cargo_directives(false)
        .end_effector("a-b")
        .frames(dyngen_codegen::description::FrameSelection::AllLinks)
        .functions(&[dyngen_codegen::FunctionGroup::Frames])
        .compile_report()
        .unwrap_or_else(|e| panic!("{e}"));
    let code = &report.robot.code;
    for variant in ["AB", "Link1", "Link1_2", "AB2"] {
        assert!(code.contains(&format!("    {variant},\n")), "variant {variant}");
    }
    assert_eq!(
        report
            .robot
            .notes
            .iter()
            .filter(|n| n.contains("both spelled"))
            .count(),
        2
    );
    write_crate(krate, "generated-twins", &["robot"]);
    let (success, _, stderr) = cargo(krate, &["build", "--lib"]);
    assert!(success, "the generated crate does not build cleanly:\n{stderr}");
}
