//! Mimic joints and joint-level terms (armature, friction, offset) on a floating base, on random
//! trees (branches, prismatic joints, skew axes, random couplings across branches), against what
//! uses no floating algorithm:
//! - with the base pinned (at the world's origin, at rest) the joint block of `D`, `C`, `g`,
//!   `τ`, the Slotine–Li torque, the regressor (bodies' and joint-level columns), the
//!   derivatives of `τ` and the frames' `J` and `J̇` are the fixed-base robot's with the same
//!   couplings and terms;
//! - each regressor column against the torque's difference in that parameter (`τ` is linear in
//!   θ), `∂τ/∂ν` and forward dynamics' derivatives against central differences, forward
//!   dynamics against inverse dynamics, `D⁻¹` against `D`;
//! - base parameters: `Y_b θ_b = Y θ` for any θ, their number the rank of the regressor stacked
//!   at other states;
//! - the traced graph (what generated code computes, through the interpreter) against the
//!   generic `f64` dynamics with the same parameters, function by function, to 1e-12.

use dyngen_testkit as common;

use common::joint_terms::with_joint_terms;
use common::random_model::{
    arb_inertia, arb_model, deterministic_runner, random_floating_sample, random_state, with_random_mimics,
    FloatingSample, SplitMix64,
};
use common::{assert_close, column, scaled_rank};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::dynamics::{FloatingDynamics, FloatingState, NumericDynamics};
use dyngen_codegen::internals::generate::{trace, Arguments, SymbolicRobot};
use dyngen_codegen::model::{Body, Inertia, Model};
use dyngen_runtime::ReferenceFrame;
use nalgebra::DMatrix;
use proptest::prelude::*;

/// Identities that hold in exact arithmetic, relative to the largest entry (at least 1).
const TOL: f64 = 1e-9;
/// Central differences (step `H`), relative.
const FD_TOL: f64 = 1e-6;
const H: f64 = 1e-6;

/// The robot of `fixed` (its couplings and joint terms) on a free-flying base of inertia `base`.
fn floating(fixed: &Model, base: Inertia) -> Model {
    let body = Body {
        name: "base".into(),
        inertia: base,
    };
    fixed
        .clone()
        .with_floating_base(body)
        .expect("a valid floating model")
}

/// A random tree with, by `seed`, random mimic joints or every kind of joint term (never both:
/// a model refuses them together, on either base), Coulomb friction smoothed half of the time.
fn coupled_or_with_terms(model: Model, seed: u64) -> Model {
    match seed % 2 {
        0 => with_random_mimics(model, seed),
        _ => with_joint_terms(model, (seed % 4 == 1).then_some(0.05), seed),
    }
}

fn block(m: &DMatrix<f64>, rows: usize, cols: usize) -> DMatrix<f64> {
    m.view((rows, cols), (m.nrows() - rows, m.ncols() - cols))
        .into_owned()
}

fn pinned(joints: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; 6];
    out.extend_from_slice(joints);
    out
}

/// The joint block of every quantity with the base pinned is the fixed-base robot's.
fn check_pinned(fixed: &Model, on_base: &Model, seed: u64) {
    let (fixed_dynamics, dynamics) = (
        NumericDynamics::new(fixed),
        FloatingDynamics::new(on_base).unwrap(),
    );
    let j = random_state(fixed, seed);
    let mut q = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    q.extend(&j.q);
    let s = dynamics.state(&q).unwrap();
    let [qd, v, qdd, a] = [&j.qd, &j.v, &j.qdd, &j.a].map(|x| pinned(x));
    let what = |x: &str| format!("{} pinned, seed {seed}: {x}", fixed.name());
    let joints = |x: nalgebra::DVector<f64>| column(&x.as_slice()[6..]);
    let pairs = [
        (
            "D",
            block(&dynamics.mass_matrix(&s), 6, 6),
            fixed_dynamics.mass_matrix(&j.q),
        ),
        (
            "C",
            block(&dynamics.coriolis_matrix(&s, &qd), 6, 6),
            fixed_dynamics.coriolis_matrix(&j.q, &j.qd),
        ),
        (
            "g",
            joints(dynamics.gravity(&s)),
            column(fixed_dynamics.gravity_torque(&j.q).as_slice()),
        ),
        (
            "τ",
            joints(dynamics.inverse_dynamics(&s, &qd, &qdd)),
            column(fixed_dynamics.inverse_dynamics(&j.q, &j.qd, &j.qdd).as_slice()),
        ),
        (
            "Slotine–Li",
            joints(dynamics.slotine_li(&s, &qd, &v, &a)),
            column(
                fixed_dynamics
                    .slotine_li(&j.q, &j.qd, &j.v, &j.a, true)
                    .as_slice(),
            ),
        ),
        (
            "Y (the base body's ten columns left out)",
            block(&dynamics.regressor(&s, &qd, &v, &a), 6, 10),
            fixed_dynamics.regressor(&j.q, &j.qd, &j.v, &j.a),
        ),
    ];
    for (name, actual, expected) in pairs {
        assert_close(&what(name), &actual, &expected, TOL);
    }
    let (dq, dv) = dynamics.inverse_dynamics_derivatives(&s, &qd, &qdd);
    let (fixed_dq, fixed_dv) = fixed_dynamics.inverse_dynamics_derivatives(&j.q, &j.qd, &j.qdd);
    assert_close(&what("∂τ/∂q"), &block(&dq, 6, 6), &fixed_dq, TOL);
    assert_close(&what("∂τ/∂ν"), &block(&dv, 6, 6), &fixed_dv, TOL);
    let lwa = ReferenceFrame::LocalWorldAligned;
    for (k, frame) in fixed.frames().iter().enumerate() {
        let motion = fixed_dynamics.frame_motion(&frame.name, &j.q, &j.qd).unwrap();
        let jacobian = dynamics.frame_jacobian(&s, k, lwa);
        assert_close(&what("J"), &block(&jacobian, 0, 6), &motion.jacobian(lwa), TOL);
        let jdot = dynamics.frame_jacobian_time_variation(&s, &qd, k, lwa);
        assert_close(
            &what("J̇"),
            &block(&jdot, 0, 6),
            &motion.jacobian_time_variation(lwa),
            TOL,
        );
    }
}

/// `x + h·e_k`.
fn moved(x: &[f64], k: usize, h: f64) -> Vec<f64> {
    let mut out = x.to_vec();
    out[k] += h;
    out
}

/// The columns of `f`'s central differences along each velocity coordinate, `f` of one.
fn differences(nv: usize, f: impl Fn(usize, f64) -> Vec<f64>) -> DMatrix<f64> {
    let columns: Vec<_> = (0..nv)
        .map(|k| {
            let (plus, minus) = (f(k, H), f(k, -H));
            column(
                &plus
                    .iter()
                    .zip(&minus)
                    .map(|(p, m)| (p - m) / (2.0 * H))
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    DMatrix::from_columns(&columns.iter().map(|c| c.column(0)).collect::<Vec<_>>())
}

/// Identities and differences at a random floating state.
fn check_floating(model: &Model, sample: &FloatingSample, seed: u64) {
    let dynamics = FloatingDynamics::new(model).unwrap();
    let s = dynamics.state(&sample.q).unwrap();
    let FloatingSample { q, v, a, vr, ar } = sample;
    let what = |x: &str| format!("{} on a floating base, seed {seed}: {x}", model.name());
    let nv = model.nv();
    // Y θ is the Slotine–Li torque, and each column is the torque's change with its parameter.
    let theta = dynamics.parameters();
    assert_eq!(theta.len(), FloatingDynamics::parameter_names(model).len());
    let y = dynamics.regressor(&s, v, vr, ar);
    let torque = |theta: &[f64]| {
        let at = FloatingDynamics::with_parameters(model, theta).unwrap();
        at.slotine_li(&at.state(q).unwrap(), v, vr, ar)
    };
    assert_close(
        &what("Y θ"),
        &(&y * column(&theta)),
        &column(torque(&theta).as_slice()),
        TOL,
    );
    for k in 0..theta.len() {
        let change = (torque(&moved(&theta, k, 1.0)) - torque(&moved(&theta, k, -1.0))) / 2.0;
        assert_close(
            &what(&format!("column {k} of Y")),
            &y.columns(k, 1).into_owned(),
            &column(change.as_slice()),
            TOL,
        );
    }
    // Forward dynamics inverts inverse dynamics; D⁻¹ inverts D.
    let tau = dynamics.inverse_dynamics(&s, v, a);
    let forward = dynamics.forward_dynamics(&s, v, tau.as_slice());
    assert_close(&what("FD(ID(a))"), &column(forward.as_slice()), &column(a), TOL);
    let identity = dynamics.mass_matrix_inverse(&s) * dynamics.mass_matrix(&s);
    assert_close(&what("D⁻¹ D"), &identity, &DMatrix::identity(nv, nv), TOL);
    // Derivatives against central differences (q moved on the manifold).
    let at = |q: &[f64]| dynamics.state(q).unwrap();
    let along = |k: usize, h: f64| dynamics.integrate(q, &moved(&vec![0.0; nv], k, 1.0), h).unwrap();
    let (dq, dv) = dynamics.inverse_dynamics_derivatives(&s, v, a);
    let fd_dq = differences(nv, |k, h| {
        dynamics
            .inverse_dynamics(&at(&along(k, h)), v, a)
            .as_slice()
            .to_vec()
    });
    let fd_dv = differences(nv, |k, h| {
        dynamics
            .inverse_dynamics(&s, &moved(v, k, h), a)
            .as_slice()
            .to_vec()
    });
    assert_close(&what("∂τ/∂q"), &dq, &fd_dq, FD_TOL);
    assert_close(&what("∂τ/∂ν"), &dv, &fd_dv, FD_TOL);
    let t = tau.as_slice();
    let (dq, dv) = dynamics.forward_dynamics_derivatives(&s, v, t);
    let fd_dq = differences(nv, |k, h| {
        dynamics
            .forward_dynamics(&at(&along(k, h)), v, t)
            .as_slice()
            .to_vec()
    });
    let fd_dv = differences(nv, |k, h| {
        dynamics
            .forward_dynamics(&s, &moved(v, k, h), t)
            .as_slice()
            .to_vec()
    });
    assert_close(&what("∂ν̇/∂q"), &dq, &fd_dq, FD_TOL);
    assert_close(&what("∂ν̇/∂ν"), &dv, &fd_dv, FD_TOL);
}

/// The base parameters reproduce `Y θ` for a random θ, and their number is the rank of the
/// regressor stacked at states other than the selection's.
fn check_base_parameters(model: &Model, base: &BaseParameterSet, seed: u64) {
    let dynamics = FloatingDynamics::new(model).unwrap();
    let mut rng = SplitMix64::new(seed);
    let theta: Vec<f64> = (0..base.standard_count)
        .map(|_| rng.uniform((-1.0, 1.0)))
        .collect();
    assert_eq!(base.standard_count, FloatingDynamics::parameter_count(model));
    let mut blocks = Vec::new();
    // More rows than columns, and enough states that Coulomb friction's sign changes.
    let states = 12 + base.standard_count / model.nv();
    for k in 0..states as u64 {
        let sample = random_floating_sample(model, 7000 + seed + k);
        let s = dynamics.state(&sample.q).unwrap();
        let y = dynamics.regressor(&s, &sample.v, &sample.vr, &sample.ar);
        let y_theta = &y * column(&theta);
        let y_b_theta_b = base.base_regressor(&y) * column(&base.base_parameters(&theta));
        assert_close(&format!("{}: Y_b θ_b", model.name()), &y_b_theta_b, &y_theta, TOL);
        blocks.push(y);
    }
    let p = blocks[0].ncols();
    let rows = blocks[0].nrows();
    let stacked = DMatrix::from_fn(rows * blocks.len(), p, |i, j| blocks[i / rows][(i % rows, j)]);
    assert_eq!(
        base.count(),
        scaled_rank(&stacked).0,
        "{}: {:?}",
        model.name(),
        base.diagnostics
    );
}

/// Every traced function (interpreted) against the generic dynamics of the parameters it was
/// traced with (the base parameters' representative ones).
fn check_traced(model: &Model, traced: &SymbolicRobot, sample: &FloatingSample) {
    let representative = traced
        .base
        .representative(&FloatingDynamics::new(model).unwrap().parameters());
    let dynamics = FloatingDynamics::with_parameters(model, &representative).unwrap();
    let FloatingSample { q, v, a, vr, ar } = sample;
    let s: FloatingState = dynamics.state(q).unwrap();
    let nv = model.nv();
    let tau = dynamics.inverse_dynamics(&s, v, a).as_slice().to_vec();
    let eval = |name: &str, qd: &[f64], v: &[f64], a: &[f64], tau: &[f64]| {
        let args = Arguments {
            q,
            qd,
            v,
            a,
            tau,
            ..Arguments::default()
        };
        traced
            .evaluate_with(name, &args)
            .unwrap_or_else(|| panic!("{name} is not traced"))
    };
    let square = |x: Vec<f64>| DMatrix::from_column_slice(nv, nv, &x);
    let pair = |x: Vec<f64>| (square(x[..nv * nv].to_vec()), square(x[nv * nv..].to_vec()));
    let none: &[f64] = &[];
    let y = dynamics.regressor(&s, v, vr, ar);
    let (dq, dv) = dynamics.inverse_dynamics_derivatives(&s, v, a);
    let (traced_dq, traced_dv) = pair(eval("inverse_dynamics_derivatives", v, none, a, none));
    let (fq, fv) = dynamics.forward_dynamics_derivatives(&s, v, &tau);
    let (traced_fq, traced_fv) = pair(eval("forward_dynamics_derivatives", v, none, none, &tau));
    let lwa = ReferenceFrame::LocalWorldAligned;
    let snake = model.frames()[0].name.to_lowercase();
    let frame_jacobian = format!("frame_jacobian_{snake}_local_world_aligned");
    let frame_jdot = format!("frame_jacobian_time_variation_{snake}_local_world_aligned");
    let pairs = [
        (
            "mass_matrix",
            square(eval("mass_matrix", none, none, none, none)),
            dynamics.mass_matrix(&s),
        ),
        (
            "coriolis_matrix",
            square(eval("coriolis_matrix", v, none, none, none)),
            dynamics.coriolis_matrix(&s, v),
        ),
        (
            "gravity",
            column(&eval("gravity", none, none, none, none)),
            column(dynamics.gravity(&s).as_slice()),
        ),
        (
            "inverse_dynamics",
            column(&eval("inverse_dynamics", v, none, a, none)),
            column(&tau),
        ),
        (
            "slotine_li",
            column(&eval("slotine_li", v, vr, ar, none)),
            column(dynamics.slotine_li(&s, v, vr, ar).as_slice()),
        ),
        (
            "regressor",
            DMatrix::from_column_slice(nv, y.ncols(), &eval("regressor", v, vr, ar, none)),
            y.clone(),
        ),
        (
            "base_regressor",
            DMatrix::from_column_slice(nv, traced.base.count(), &eval("base_regressor", v, vr, ar, none)),
            traced.base.base_regressor(&y),
        ),
        (
            "forward_dynamics",
            column(&eval("forward_dynamics", v, none, none, &tau)),
            column(dynamics.forward_dynamics(&s, v, &tau).as_slice()),
        ),
        (
            "mass_matrix_inverse",
            square(eval("mass_matrix_inverse", none, none, none, none)),
            dynamics.mass_matrix_inverse(&s),
        ),
        ("∂τ/∂q", traced_dq, dq),
        ("∂τ/∂ν", traced_dv, dv),
        ("∂ν̇/∂q", traced_fq, fq),
        ("∂ν̇/∂ν", traced_fv, fv),
        (
            "centroidal_momentum_matrix",
            DMatrix::from_column_slice(6, nv, &eval("centroidal_momentum_matrix", none, none, none, none)),
            dynamics.centroidal_momentum_matrix(&s).2,
        ),
        (
            "centroidal_bias",
            column(&eval("centroidal_bias", v, none, none, none)),
            column(dynamics.centroidal_bias(&s, v).as_slice()),
        ),
        (
            "the end-effector's J",
            DMatrix::from_column_slice(6, nv, &eval(&frame_jacobian, none, none, none, none)),
            dynamics.frame_jacobian(&s, 0, lwa),
        ),
        (
            "the end-effector's J̇",
            DMatrix::from_column_slice(6, nv, &eval(&frame_jdot, v, none, none, none)),
            dynamics.frame_jacobian_time_variation(&s, v, 0, lwa),
        ),
    ];
    for (name, actual, expected) in pairs {
        assert_close(
            &format!("{}: traced {name}", model.name()),
            &actual,
            &expected,
            1e-12,
        );
    }
}

/// Random trees with random couplings or joint terms, pinned and free.
#[test]
fn random_trees_with_couplings_or_joint_terms() {
    let strategy = (arb_model(5), arb_inertia(), any::<u64>());
    let result = deterministic_runner(24).run(&strategy, |(model, base, seed)| {
        let fixed = coupled_or_with_terms(model, seed);
        let on_base = floating(&fixed, base);
        check_pinned(&fixed, &on_base, seed);
        for k in 0..2 {
            check_floating(&on_base, &random_floating_sample(&on_base, seed ^ k), seed);
        }
        let traced = trace(&on_base);
        check_base_parameters(&on_base, &traced.base, seed);
        check_traced(&on_base, &traced, &random_floating_sample(&on_base, seed ^ 9));
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}
