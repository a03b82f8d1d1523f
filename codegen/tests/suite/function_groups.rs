//! Choosing the groups of functions to generate: the description's `functions:`, the
//! `Builder`, the default by size, the errors, and that a function computes the same whichever
//! other groups are generated with it.

use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::{load, Choices};
use dyngen_codegen::generate::{generate_robot, generate_robot_with, GeneratedRobot, Shapes};
use dyngen_codegen::internals::generate::{trace_functions, Arguments};
use dyngen_codegen::{Builder, FunctionGroup, Functions, EVERY_GROUP_BY_DEFAULT_UP_TO_DOF};
use dyngen_runtime::SplitMix64;
use dyngen_testkit::workspace_root;
use std::path::{Path, PathBuf};

/// `robots/arm7.yaml` with `extra` appended, written into `dir`.
fn arm7_with(dir: &Path, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(workspace_root().join("robots/arm7.yaml")).expect("arm7");
    let path = dir.join("arm7.yaml");
    std::fs::write(&path, format!("{text}\n{extra}\n")).expect("write");
    path
}

fn generate(path: &Path) -> GeneratedRobot {
    generate_robot(path, "arm7.yaml", "Arm7", "test").unwrap_or_else(|e| panic!("{e}"))
}

/// The text of generated method `name` (its doc comment and body), from `fn name(` to the end
/// of its block at the same indentation.
fn method(code: &str, name: &str) -> Option<String> {
    let lines: Vec<&str> = code.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim_start().starts_with(&format!("fn {name}(")))?;
    let indent = &lines[start][..lines[start].len() - lines[start].trim_start().len()];
    let end = (start..lines.len()).find(|&k| lines[k] == format!("{indent}}}"))?;
    Some(lines[start..=end].join("\n"))
}

fn functions_of(robot: &GeneratedRobot) -> Vec<&str> {
    robot.op_counts.iter().map(|(name, _)| name.as_str()).collect()
}

#[test]
fn a_description_chooses_its_groups_and_gets_exactly_their_traits() {
    let dir = tempfile::tempdir().expect("dir");
    let robot = generate(&arm7_with(dir.path(), "functions: [forward_dynamics]"));
    assert_eq!(
        robot.functions,
        Functions::with(&[FunctionGroup::ForwardDynamics]).unwrap()
    );
    for present in [
        "impl Kinematics<7>",
        "impl RobotDynamics<7, 70>",
        "impl ForwardDynamics<7, 70>",
    ] {
        assert!(robot.code.contains(present), "{present} missing");
    }
    for absent in [
        "impl Regressors",
        "impl BaseParameters",
        "impl LaneDynamics",
        "impl DynamicsDerivatives",
    ] {
        assert!(
            !robot.code.contains(absent),
            "{absent} generated without being chosen"
        );
    }
    assert_eq!(
        functions_of(&robot),
        [
            "forward_kinematics",
            "jacobian",
            "jacobian_dot",
            "mass_matrix",
            "coriolis_matrix",
            "gravity",
            "inverse_dynamics",
            "slotine_li",
            "forward_dynamics",
            "mass_matrix_inverse",
            "kinematics"
        ]
    );
}

#[test]
fn every_group_is_the_default_of_a_small_robot_and_all_is_the_committed_code() {
    let dir = tempfile::tempdir().expect("dir");
    let all = generate(&arm7_with(dir.path(), "functions: all"));
    let committed = std::fs::read_to_string(workspace_root().join("generated/src/arm7.rs")).expect("arm7.rs");
    // Every group but `contacts`, which only a robot with contacts has.
    assert_eq!(all.functions, Functions::all().without(FunctionGroup::Contacts));
    for (name, _) in &all.op_counts {
        assert_eq!(method(&all.code, name), method(&committed, name), "{name}");
    }
}

/// A group traced without the groups before it in the trace order computes the same values:
/// the statements' order may differ (nodes shared with a group left out are created later),
/// the function may not. On a floating base as on a fixed one.
#[test]
fn a_function_computes_the_same_whatever_is_generated_with_it() {
    use FunctionGroup as G;
    let choices = [
        vec![],
        vec![G::ForwardDynamics],
        vec![G::Derivatives],
        vec![G::Regressors],
        vec![G::Regressors, G::BaseParameters, G::Derivatives],
        vec![G::Frames],
        vec![G::ForwardDynamics, G::Frames, G::Contacts],
    ];
    for robot in ["arm7_friction.yaml", "solo12.yaml"] {
        let model = load(&workspace_root().join("robots").join(robot))
            .unwrap_or_else(|e| panic!("{e}"))
            .model;
        let base = BaseParameterSet::compute(&model);
        let full = trace_functions(&model, base.clone(), Functions::all(), &Shapes::flat());
        let floating = model.floating_base().is_some();
        let (nq, nv) = (model.nq(), model.nv());
        let p = match floating {
            true => 10 * (model.joints().len() + 1),
            false => model.parameter_count(),
        };
        let mut rng = SplitMix64::new(5);
        let mut vector = |len: usize| -> Vec<f64> { (0..len).map(|_| rng.uniform((-1.5, 1.5))).collect() };
        let states: Vec<[Vec<f64>; 7]> = (0..3)
            .map(|_| {
                let mut q = vector(nq);
                if floating {
                    let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
                    q[3..7].iter_mut().for_each(|x| *x /= norm);
                }
                [
                    q,
                    vector(nv),
                    vector(nv),
                    vector(nv),
                    vector(nv),
                    vector(p),
                    vector(nv),
                ]
            })
            .collect();
        for chosen in &choices {
            // `contacts` is traced only for a robot with contacts (Solo-12 holds its feet).
            if chosen.contains(&G::Contacts) && model.contacts().is_empty() {
                continue;
            }
            let functions = Functions::with(chosen).unwrap();
            let partial = trace_functions(&model, base.clone(), functions, &Shapes::flat());
            let names: Vec<String> = partial.quantities.iter().map(|q| q.name()).collect();
            let expected: Vec<String> = full
                .quantities
                .iter()
                .filter(|q| functions.contains(q.kind.group()))
                .map(|q| q.name())
                .collect();
            assert_eq!(names, expected, "{robot}: {functions}");
            for [q, qd, v, a, tau, theta, r] in &states {
                let args = Arguments {
                    q,
                    qd,
                    v,
                    a,
                    tau,
                    theta,
                    r,
                    ..Arguments::default()
                };
                for name in &names {
                    let got = partial.evaluate_with(name, &args).expect("traced");
                    let want = full.evaluate_with(name, &args).expect("traced");
                    let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
                    for (g, w) in got.iter().zip(&want) {
                        assert!(
                            (g - w).abs() <= 1e-12 * scale,
                            "{robot}: {name} with [{functions}]: {g} against {w}"
                        );
                    }
                }
            }
        }
    }
}

/// A floating base takes its groups as a fixed one does: what its description chooses, each
/// group its floating trait, nothing else.
#[test]
fn a_floating_description_chooses_its_groups() {
    let dir = tempfile::tempdir().expect("dir");
    let text = std::fs::read_to_string(workspace_root().join("robots/solo12.yaml")).expect("solo12");
    let text = text.replace(
        "urdf: urdf/",
        &format!("urdf: {}/", workspace_root().join("robots/urdf").display()),
    );
    let path = dir.path().join("solo12.yaml");
    std::fs::write(&path, format!("{text}\nfunctions: [forward_dynamics, frames]\n")).expect("write");
    let robot = generate_robot(&path, "solo12.yaml", "Solo12", "test").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        robot.functions,
        Functions::with(&[FunctionGroup::ForwardDynamics, FunctionGroup::Frames]).unwrap()
    );
    for present in [
        "impl FloatingBaseDynamics<12, 18, 130>",
        "impl FloatingForwardDynamics<12, 18, 130>",
        "impl FloatingFrameKinematics<12, 18>",
    ] {
        assert!(robot.code.contains(present), "{present} missing");
    }
    for absent in [
        "impl FloatingRegressors",
        "impl FloatingBaseParameters",
        "impl FloatingDynamicsDerivatives",
        "impl ContactDynamics",
        "fn regressor(",
        "fn inverse_dynamics_derivatives(",
    ] {
        assert!(
            !robot.code.contains(absent),
            "{absent} generated without being chosen"
        );
    }
}

#[test]
fn unknown_groups_and_unmet_needs_are_errors_at_the_key() {
    let dir = tempfile::tempdir().expect("dir");
    let path = arm7_with(dir.path(), "functions: [regressors, derivative]");
    let e = generate_robot(&path, "arm7.yaml", "Arm7", "test").expect_err("unknown group");
    let message = e.to_string();
    assert!(message.contains("arm7.yaml:"), "{message}");
    assert!(
        message.contains("`derivative`") && message.contains("derivatives"),
        "{message}"
    );
    // The key's line: the last line of the file.
    let line = std::fs::read_to_string(&path).unwrap().lines().count();
    assert!(
        message.contains(&format!(":{line}:")),
        "no line {line}: {message}"
    );

    let path = arm7_with(dir.path(), "functions: [base_parameters]");
    let e = generate_robot(&path, "arm7.yaml", "Arm7", "test").expect_err("needs regressors");
    assert!(
        e.to_string().contains("`base_parameters` needs `regressors`"),
        "{e}"
    );
}

#[test]
fn the_builder_chooses_for_a_urdf_and_refuses_a_second_choice() {
    let dir = tempfile::tempdir().expect("dir");
    let urdf = workspace_root().join("robots/urdf/ur5_robot.urdf");
    let builder = |description: &Path, groups: &[FunctionGroup]| {
        Builder::new(description)
            .out_dir(dir.path())
            .cargo_directives(false)
            .functions(groups)
    };
    let report = builder(&urdf, &[FunctionGroup::Regressors])
        .compile_report()
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(report.robot.code.contains("impl Regressors<6, 60>"));
    assert!(!report.robot.code.contains("impl ForwardDynamics"));

    let yaml = arm7_with(dir.path(), "functions: all");
    let e = builder(&yaml, &[FunctionGroup::Derivatives])
        .compile()
        .expect_err("chosen twice");
    assert!(e.to_string().contains("chosen twice"), "{e}");

    let e = builder(&urdf, &[FunctionGroup::BaseParameters])
        .compile()
        .expect_err("needs regressors");
    assert!(e.to_string().contains("needs `regressors`"), "{e}");
}

/// A chain of `n` revolute joints, light links, written as a YAML description.
fn chain(n: usize) -> String {
    let mut links = String::from("  - name: base\n");
    let mut joints = String::new();
    for i in 1..=n {
        links += &format!(
            "  - name: l{i}\n    inertial:\n      mass: 1.0\n      origin: {{ xyz: [0.05, 0.0, 0.1] }}\n      \
             inertia: {{ ixx: 0.01, ixy: 0.0, ixz: 0.0, iyy: 0.012, iyz: 0.0, izz: 0.008 }}\n"
        );
        let parent = if i == 1 {
            "base".to_owned()
        } else {
            format!("l{}", i - 1)
        };
        let axis = if i % 2 == 0 { "[0, 1, 0]" } else { "[0, 0, 1]" };
        joints += &format!(
            "  - name: j{i}\n    type: revolute\n    parent: {parent}\n    child: l{i}\n    \
             origin: {{ xyz: [0, 0, 0.2] }}\n    axis: {axis}\n    \
             limit: {{ lower: -3, upper: 3, velocity: 2, effort: 100 }}\n"
        );
    }
    format!("name: chain\nlinks:\n{links}joints:\n{joints}")
}

#[test]
fn large_robots_get_the_per_tick_groups_by_default_and_say_so() {
    let dir = tempfile::tempdir().expect("dir");
    let dof = EVERY_GROUP_BY_DEFAULT_UP_TO_DOF + 1;
    let path = dir.path().join("chain.yaml");
    std::fs::write(&path, chain(dof)).expect("write");
    let generate = |functions: Option<Functions>| {
        let choices = Choices {
            functions,
            ..Choices::default()
        };
        generate_robot_with(&path, "chain.yaml", "Chain", "test", &choices).unwrap_or_else(|e| panic!("{e}"))
    };
    let robot = generate(None);
    assert_eq!(robot.model.dof(), dof);
    assert_eq!(
        robot.functions,
        Functions::default_for(dof).without(FunctionGroup::Contacts)
    );
    assert!(!robot.functions.contains(FunctionGroup::Derivatives));
    assert!(!robot.code.contains("impl DynamicsDerivatives"));
    assert!(!robot.code.contains("impl Regressors"));
    assert!(robot.code.contains("impl ForwardDynamics") && robot.code.contains("impl FrameKinematics"));
    assert!(
        robot.notes.iter().any(|n| n
            .contains("regressors, base_parameters, derivatives are generated when chosen")
            && n.contains("functions:")),
        "{:?}",
        robot.notes
    );
    // On a floating base, the same default and the same note.
    let floating = dir.path().join("floating_chain.yaml");
    std::fs::write(&floating, chain(dof) + "floating_base: true\n").expect("write");
    let robot = generate_robot(&floating, "floating_chain.yaml", "FloatingChain", "test")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        robot.functions,
        Functions::default_for(dof).without(FunctionGroup::Contacts)
    );
    assert!(!robot.code.contains("impl FloatingDynamicsDerivatives"));
    assert!(!robot.code.contains("impl FloatingRegressors"));
    assert!(
        robot.code.contains("impl FloatingForwardDynamics")
            && robot.code.contains("impl FloatingFrameKinematics")
    );
    assert!(
        robot
            .notes
            .iter()
            .any(|n| n.contains("regressors, base_parameters, derivatives are generated when chosen")),
        "{:?}",
        robot.notes
    );
    // Chosen explicitly, the same robot gets only what it asks for, and no note.
    let chosen = Functions::with(&[FunctionGroup::ForwardDynamics]).unwrap();
    let robot = generate(Some(chosen));
    assert_eq!(robot.functions, chosen);
    assert!(
        robot.notes.iter().all(|n| !n.contains("derivatives")),
        "{:?}",
        robot.notes
    );
}
