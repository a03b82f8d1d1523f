//! Joint-level parameters (armature, viscous and Coulomb friction, offset): each regressor
//! column against its direct formula and finite differences, the torque functions against
//! `Y θ`, the symbolic graph against the numeric dynamics, the base parameters with joint
//! terms on the reference arms and random trees, and the descriptions that choose them.

use dyngen_testkit as common;

use common::joint_terms::with_joint_terms;
use common::random_model::{arb_model_and_state, deterministic_runner, random_state};
use dyngen_codegen::base_parameters::{BaseParameterSet, SVD_RANK_TOL};
use dyngen_codegen::description::{load, load_yaml_str};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::base_parameters::{numerical_rank, stacked_regressor};
use dyngen_codegen::internals::generate::trace;
use dyngen_codegen::model::{JointTermKind, JointTermValues, JointTerms, Model};
use nalgebra::{DMatrix, DVector};
use std::path::Path;

fn robot(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../robots")
        .join(format!("{name}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// The same model without joint terms.
fn rigid(model: &Model) -> Model {
    model
        .clone()
        .with_joint_terms(JointTerms::default())
        .expect("valid")
}

fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Every joint-level column equals its formula (`a_j`, `v_j`, `σ(q̇_j)`, `1` in row `j`, 0
/// elsewhere), the inertial block is the rigid-body regressor, and `Y θ` adds exactly
/// `Ia a + fv v + fc σ(q̇) + fo` to the rigid-body Slotine–Li torque.
#[test]
fn joint_columns_match_their_formulas() {
    for name in ["arm7", "panda", "ur5"] {
        for smoothing in [None, Some(0.05)] {
            let model = with_joint_terms(robot(name), smoothing, 7);
            let rigid_model = rigid(&model);
            let (n, p) = (model.dof(), model.parameter_count());
            assert_eq!(p, 14 * n);
            let dynamics = NumericDynamics::new(&model);
            let rigid_dynamics = NumericDynamics::new(&rigid_model);
            for seed in 0..20 {
                let mut s = random_state(&model, seed);
                if seed == 0 {
                    s.qd[0] = 0.0; // Coulomb friction vanishes at rest
                }
                let y = dynamics.regressor(&s.q, &s.qd, &s.v, &s.a);
                let y_rigid = rigid_dynamics.regressor(&s.q, &s.qd, &s.v, &s.a);
                assert_eq!(y.shape(), (n, p));
                assert_eq!(y.columns(0, 10 * n), y_rigid.columns(0, 10 * n));
                for j in 0..n {
                    let sigma = match smoothing {
                        None => sign(s.qd[j]),
                        Some(eps) => (s.qd[j] / eps).tanh(),
                    };
                    let expected = [s.a[j], s.v[j], sigma, 1.0];
                    for (pos, kind) in JointTermKind::ALL.into_iter().enumerate() {
                        let col = model.joint_term_index(j, kind).expect("every kind is a column");
                        assert_eq!(col, 10 * n + 4 * j + pos);
                        for row in 0..n {
                            let want = if row == j { expected[pos] } else { 0.0 };
                            assert_eq!(y[(row, col)], want, "{name}: {kind:?} of joint {j}, row {row}");
                        }
                    }
                }
                let theta = DVector::from_vec(model.parameters());
                let tau = &y * &theta;
                let tau_rigid = rigid_dynamics.slotine_li(&s.q, &s.qd, &s.v, &s.a, true);
                for j in 0..n {
                    let v = model.joint_terms().value(j);
                    let sigma = match smoothing {
                        None => sign(s.qd[j]),
                        Some(eps) => (s.qd[j] / eps).tanh(),
                    };
                    let joint = v.armature * s.a[j] + v.viscous * s.v[j] + v.coulomb * sigma + v.offset;
                    let err = (tau[j] - tau_rigid[j] - joint).abs();
                    assert!(
                        err <= 1e-12 * (1.0 + tau[j].abs()),
                        "{name}: joint {j} torque off by {err}"
                    );
                }
            }
        }
    }
}

/// `τ`, the Slotine–Li torque and `D` of the numeric dynamics include the joint terms, and
/// agree with `Y θ` and with finite differences: `∂τ/∂q̈ = D` (armature on the diagonal),
/// `∂(Y θ)/∂v = C + diag(fv)`.
#[test]
fn torques_and_mass_matrix_include_joint_terms() {
    let model = with_joint_terms(robot("arm7"), None, 11);
    let rigid_model = rigid(&model);
    let dynamics = NumericDynamics::new(&model);
    let rigid_dynamics = NumericDynamics::new(&rigid_model);
    let theta = DVector::from_vec(model.parameters());
    let n = model.dof();
    for seed in 100..110 {
        let s = random_state(&model, seed);
        let tau = dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd);
        let y = dynamics.regressor(&s.q, &s.qd, &s.qd, &s.qdd);
        assert!((&tau - &y * &theta).amax() <= 1e-10 * (1.0 + tau.amax()));
        let sl = dynamics.slotine_li(&s.q, &s.qd, &s.v, &s.a, true);
        let y = dynamics.regressor(&s.q, &s.qd, &s.v, &s.a);
        assert!((&sl - &y * &theta).amax() <= 1e-10 * (1.0 + sl.amax()));
        // D by central differences of τ in q̈ (τ is affine in q̈: exact up to rounding).
        let d = dynamics.mass_matrix(&s.q);
        let h = 1e-3;
        let fd = DMatrix::from_fn(n, n, |_, _| 0.0);
        let mut fd = fd;
        for k in 0..n {
            let (mut up, mut down) = (s.qdd.clone(), s.qdd.clone());
            up[k] += h;
            down[k] -= h;
            let col = (dynamics.inverse_dynamics(&s.q, &s.qd, &up)
                - dynamics.inverse_dynamics(&s.q, &s.qd, &down))
                / (2.0 * h);
            fd.set_column(k, &col);
        }
        assert!(
            (&d - &fd).amax() <= 1e-8 * d.amax(),
            "D against finite differences"
        );
        let d_rigid = rigid_dynamics.mass_matrix(&s.q);
        for j in 0..n {
            let armature = model.joint_terms().value(j).armature;
            assert!((d[(j, j)] - d_rigid[(j, j)] - armature).abs() <= 1e-12 * d.amax());
        }
        // ∂(Yθ)/∂v_k = C e_k + fv_k e_k.
        let c = rigid_dynamics.coriolis_matrix(&s.q, &s.qd);
        for k in 0..n {
            let (mut up, mut down) = (s.v.clone(), s.v.clone());
            up[k] += h;
            down[k] -= h;
            let col = (dynamics.slotine_li(&s.q, &s.qd, &up, &s.a, true)
                - dynamics.slotine_li(&s.q, &s.qd, &down, &s.a, true))
                / (2.0 * h);
            let mut want = c.column(k).into_owned();
            want[k] += model.joint_terms().value(k).viscous;
            assert!(
                (col - want).amax() <= 1e-8 * (1.0 + c.amax()),
                "∂/∂v of joint {k}"
            );
        }
    }
}

/// The traced graph (what is emitted), through the interpreter, equals the numeric dynamics
/// for every quantity the joint terms touch, with sign and with tanh.
#[test]
fn traced_graph_includes_joint_terms() {
    for smoothing in [None, Some(0.02)] {
        let model = with_joint_terms(robot("arm7"), smoothing, 3);
        let dynamics = NumericDynamics::new(&model);
        let symbolic = trace(&model);
        let n = model.dof();
        for seed in 0..10 {
            let s = random_state(&model, seed);
            let check = |name: &str, got: Vec<f64>, want: &DMatrix<f64>| {
                let got = DMatrix::from_column_slice(want.nrows(), want.ncols(), &got);
                assert!((&got - want).amax() <= 1e-10 * (1.0 + want.amax()), "{name}");
            };
            let ev = |name: &str| {
                symbolic
                    .evaluate(name, &s.q, &s.qd, &s.v, &s.a)
                    .expect("quantity")
            };
            check(
                "regressor",
                ev("regressor"),
                &dynamics.regressor(&s.q, &s.qd, &s.v, &s.a),
            );
            check("mass_matrix", ev("mass_matrix"), &dynamics.mass_matrix(&s.q));
            let sl = dynamics.slotine_li(&s.q, &s.qd, &s.v, &s.a, true);
            check(
                "slotine_li",
                ev("slotine_li"),
                &DMatrix::from_column_slice(n, 1, sl.as_slice()),
            );
            let tau = symbolic
                .evaluate("inverse_dynamics", &s.q, &s.qd, &s.v, &s.qdd)
                .expect("quantity");
            let want = dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd);
            check(
                "inverse_dynamics",
                tau,
                &DMatrix::from_column_slice(n, 1, want.as_slice()),
            );
        }
    }
}

/// Base parameters with joint terms: as many as the rank of the stacked regressor, `Y_b θ_b =
/// Y θ` at fresh states, and every joint-level column either kept or folded where expected.
fn check_base_parameters(model: &Model) -> BaseParameterSet {
    let base = BaseParameterSet::compute(model);
    let stacked = stacked_regressor(model, 60, 0x5EED);
    assert_eq!(
        base.count(),
        numerical_rank(&stacked, SVD_RANK_TOL),
        "{}: rank",
        model.name()
    );
    let dynamics = NumericDynamics::new(model);
    let theta = model.parameters();
    let theta_b = DVector::from_vec(base.base_parameters(&theta));
    let theta = DVector::from_vec(theta);
    for seed in 500..510 {
        let s = random_state(model, seed);
        let y = dynamics.regressor(&s.q, &s.qd, &s.v, &s.a);
        let full = &y * &theta;
        let reduced = base.base_regressor(&y) * &theta_b;
        assert!(
            (&full - &reduced).amax() <= 1e-9 * (1.0 + full.amax()),
            "{}: Y_b θ_b = Y θ",
            model.name()
        );
    }
    base
}

#[test]
fn base_parameters_with_joint_terms_on_reference_arms() {
    for name in ["arm7", "panda", "ur5"] {
        let rigid_model = robot(name);
        let model = with_joint_terms(rigid_model.clone(), None, 5);
        let rigid_base = BaseParameterSet::compute(&rigid_model);
        let base = check_base_parameters(&model);
        // Friction and offset columns are new directions; armature adds one, except where it
        // acts like an inertia already there (the first joint's, about a fixed vertical axis).
        let n = model.dof();
        assert!(
            base.count() >= rigid_base.count() + 3 * n,
            "{name}: {} base",
            base.count()
        );
        let index = |j: usize, kind| model.joint_term_index(j, kind).expect("column");
        let containing = |i: usize| {
            base.terms
                .iter()
                .filter(|t| t.iter().any(|&(k, _)| k == i))
                .count()
        };
        let first = base
            .terms
            .iter()
            .find(|t| t.iter().any(|&(k, _)| k == index(0, JointTermKind::Armature)))
            .expect("Ia[joint1] is in a base parameter");
        assert_eq!(
            first[0].0, 9,
            "{name}: the first joint's armature combines with the first body's Izz"
        );
        // Friction and offsets never fold (nothing else is constant, odd in q̇ or a pure v_j in
        // one row); every armature appears in exactly one base parameter.
        let mut alone = 0;
        for j in 0..n {
            for kind in [
                JointTermKind::Viscous,
                JointTermKind::Coulomb,
                JointTermKind::Offset,
            ] {
                let i = index(j, kind);
                assert!(
                    base.terms.contains(&vec![(i, 1.0)]),
                    "{name}: {kind:?} of joint {j} stands alone"
                );
            }
            let i = index(j, JointTermKind::Armature);
            assert_eq!(
                containing(i),
                1,
                "{name}: armature of joint {j} in one base parameter"
            );
            alone += usize::from(base.terms.contains(&vec![(i, 1.0)]));
        }
        assert_eq!(base.count(), rigid_base.count() + 3 * n + alone, "{name}: count");
    }
}

#[test]
fn base_parameters_with_joint_terms_on_random_trees() {
    let count = std::cell::Cell::new(0);
    let result = deterministic_runner(48).run(&arb_model_and_state(6), |(model, _)| {
        let model = with_joint_terms(model, Some(0.1), 9);
        check_base_parameters(&model);
        count.set(count.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert_eq!(count.get(), 48);
}

const TWO_JOINTS: &str = r#"
name: two
joint_parameters:
  columns: [offset, viscous, coulomb, armature]
  coulomb_smoothing: 0.01
  joints:
    elbow: { coulomb: 0.7 }
links:
  - name: base
  - name: upper
    inertial: { mass: 2.0, origin: { xyz: [0.1, 0, 0] }, inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.02, iyz: 0, izz: 0.02 } }
  - name: lower
    inertial: { mass: 1.0, origin: { xyz: [0.1, 0, 0] }, inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.01, iyz: 0, izz: 0.01 } }
joints:
  - name: shoulder
    type: revolute
    parent: base
    child: upper
    axis: [0, 0, 1]
    limit: { lower: -2, upper: 2, velocity: 2, effort: 50 }
    dynamics: { armature: 0.3, viscous: 0.8, coulomb: 2.0, offset: -0.1 }
  - name: elbow
    type: revolute
    parent: upper
    child: lower
    origin: { xyz: [0.3, 0, 0] }
    axis: [0, 1, 0]
    limit: { lower: -2, upper: 2, velocity: 2, effort: 30 }
    dynamics: { viscous: 0.4, coulomb: 5.0 }
"#;

#[test]
fn yaml_chooses_columns_and_values() {
    let model = load_yaml_str(TWO_JOINTS, Path::new("two.yaml"))
        .expect("loads")
        .model;
    let t = &model.joint_terms();
    assert_eq!(
        t.kinds,
        JointTermKind::ALL.to_vec(),
        "column order is fixed, not the file's"
    );
    assert_eq!(t.coulomb_smoothing, Some(0.01));
    assert_eq!(
        t.values[0],
        JointTermValues {
            armature: 0.3,
            viscous: 0.8,
            coulomb: 2.0,
            offset: -0.1
        }
    );
    // The wrapper's `joints.elbow.coulomb` overrides the joint's own; the rest is its own or 0.
    assert_eq!(
        t.values[1],
        JointTermValues {
            armature: 0.0,
            viscous: 0.4,
            coulomb: 0.7,
            offset: 0.0
        }
    );
    let names = model.parameter_names();
    assert_eq!(
        &names[20..24],
        ["Ia[shoulder]", "fv[shoulder]", "fc[shoulder]", "fo[shoulder]"]
    );
    assert_eq!(model.parameters()[20..24], [0.3, 0.8, 2.0, -0.1]);
    // Without `joint_parameters`, the same joints have no columns (the values are unused).
    let plain = TWO_JOINTS.replace("joint_parameters:", "unused:");
    let plain: String = plain
        .lines()
        .filter(|l| {
            !l.starts_with("unused:")
                && !l.starts_with("  columns")
                && !l.starts_with("  coulomb_smoothing")
                && !l.starts_with("  joints:")
                && !l.starts_with("    elbow: { coulomb")
        })
        .collect::<Vec<_>>()
        .join("\n");
    let model = load_yaml_str(&plain, Path::new("two.yaml")).expect("loads").model;
    assert_eq!(model.parameter_count(), 20);
}

#[test]
fn urdf_dynamics_tags_map_to_viscous_and_coulomb_friction() {
    let scratch = dyngen_testkit::scratch::scratch_dir("joint-terms");
    let dir = scratch.path();
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/urdf/panda.urdf");
    let wrapper = dir.join("panda_friction.yaml");
    std::fs::write(
        &wrapper,
        format!(
            "urdf: {}\nname: panda\nend_effector: panda_hand_tcp\nlocked_joints: {{ panda_finger_joint1: 0.0, panda_finger_joint2: 0.0 }}\n\
             joint_parameters:\n  columns: [viscous, coulomb, armature]\n  joints:\n    panda_joint7: {{ armature: 0.05, viscous: 0.5 }}\n",
            urdf.display()
        ),
    )
    .expect("write wrapper");
    let model = load(&wrapper).unwrap_or_else(|e| panic!("{e}")).model;
    let text = std::fs::read_to_string(&urdf).expect("panda.urdf");
    let doc = roxmltree::Document::parse(&text).expect("xml");
    for (j, joint) in model.joints().iter().enumerate() {
        let node = doc
            .descendants()
            .find(|n| n.has_tag_name("joint") && n.attribute("name") == Some(joint.name.as_str()))
            .expect("joint in the URDF");
        let dynamics = node.children().find(|n| n.has_tag_name("dynamics"));
        let attr = |a: &str| {
            dynamics
                .and_then(|d| d.attribute(a))
                .map_or(0.0, |v| v.parse().expect("number"))
        };
        let v = model.joint_terms().value(j);
        if joint.name == "panda_joint7" {
            assert_eq!((v.armature, v.viscous), (0.05, 0.5), "the wrapper overrides");
        } else {
            assert_eq!(
                v.viscous,
                attr("damping"),
                "{}: damping is viscous friction",
                joint.name
            );
            assert_eq!(v.armature, 0.0);
        }
        assert_eq!(
            v.coulomb,
            attr("friction"),
            "{}: friction is Coulomb friction",
            joint.name
        );
    }
    assert_eq!(model.joint_terms().per_joint(), 3);
}

fn error_of(text: &str) -> String {
    match load_yaml_str(text, Path::new("two.yaml")) {
        Ok(_) => panic!("loads, but should not:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_joint_parameters_are_errors_with_places() {
    let cases = [
        (
            TWO_JOINTS.replace("[offset, viscous", "[offset, visous"),
            "two.yaml:4:21: joint_parameters.columns[1]: unknown joint-parameter column 'visous' (expected armature, viscous, coulomb or offset)",
        ),
        (
            TWO_JOINTS.replace("[offset, viscous, coulomb, armature]", "[offset, offset]"),
            "two.yaml:4:21: joint-parameter column 'offset' is listed twice",
        ),
        (
            TWO_JOINTS.replace("coulomb_smoothing: 0.01", "coulomb_smoothing: 0"),
            "two.yaml:5:22: coulomb_smoothing 0 must be a positive number (rad/s or m/s)",
        ),
        (
            TWO_JOINTS.replace("    elbow: { coulomb: 0.7 }", "    wrist: { coulomb: 0.7 }"),
            "two.yaml:7:12: joint 'wrist': the robot has no joint of that name",
        ),
        (
            TWO_JOINTS.replace("    elbow: { coulomb: 0.7 }", "    elbow: { coulomb: -0.7 }"),
            "two.yaml:7:23: joint 'elbow': coulomb -0.7 is negative: armature and friction cannot be",
        ),
        (
            TWO_JOINTS.replace("dynamics: { viscous: 0.4,", "dynamics: { viscous: .nan,"),
            "joint 'elbow': viscous NaN is not finite",
        ),
        (
            TWO_JOINTS.replace("dynamics: { viscous: 0.4,", "dynamics: { viscus: 0.4,"),
            "unknown field `viscus`, expected one of `armature`, `viscous`, `coulomb`, `offset`",
        ),
    ];
    let wrong: Vec<String> = cases
        .iter()
        .map(|(text, want)| (error_of(text), want))
        .filter(|(got, want)| !got.contains(*want))
        .map(|(got, want)| format!("expected «{want}», got «{got}»"))
        .collect();
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
