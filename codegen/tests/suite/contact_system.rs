//! What the solves read in one call (`contact_delassus`, `contact_matrices`, `contact_system`),
//! evaluated by the interpreter: the Delassus matrix `K` (traced from the factored mass matrix,
//! `Yᵀ Δ⁻¹ Y`) is `J M⁻¹ Jᵀ` of the traced rows to rounding and exactly symmetric, and every
//! other part is the row it repeats, to the bit (the same nodes). On a floating base (Solo-12's
//! four point feet), a fixed-base chain holding its tool and a point halfway up (the
//! Panda, whose rows share a branch), two branches held tip to tip (frame loops) and the
//! four-bar, whose rows are dependent (`K` singular, still `J M⁻¹ Jᵀ`).
//!
//! And the solves in one call (`contact_solve`, `contact_proximal_solve`, `contact_impulse`,
//! `contact_forward_dynamics`, `contact_inertia`) against the equations they solve, written
//! with the parts above and dense nalgebra algebra: `(K + μ I) λ_k = rhs + μ λ_{k−1}` for each
//! step, the acceleration `a_free + M⁻¹ Jᵀ λ`, the pivots' product `det(K + μ I)`, and
//! `(K + ε I)⁻¹ (K + ε I) = I`.

use dyngen_testkit as common;

use common::{assert_close, workspace_root};
use dyngen_codegen::description::load;
use dyngen_codegen::internals::generate::{trace, Arguments, Coefficient};
use dyngen_codegen::model::{Contact, Model};
use dyngen_runtime::{ContactKind, ReferenceFrame, SplitMix64};
use nalgebra::{DMatrix, DVector};

/// `K` against `J M⁻¹ Jᵀ`, relative to its largest entry.
const TOL: f64 = 1e-12;
/// The solves' equations, relative: `K + μ I` with `μ` a tenth of `K`'s scale keeps its
/// condition number small, and the dependent rows of the four-bar solvable.
const SOLVE_TOL: f64 = 1e-10;

/// Checks the three rows at `states` random states of `model` (`floating`: its configuration
/// starts with a base position and a unit quaternion).
fn check(robot: &str, model: &Model, floating: bool, states: usize) {
    let traced = trace(model);
    let (nv, nc) = (model.nv(), model.contact_rows());
    let nq = if floating { nv + 1 } else { nv };
    let mut rng = SplitMix64::new(nv as u64 * 31 + nc as u64);
    for k in 0..states {
        let what = |q: &str| format!("{robot} state {k}: {q}");
        let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform((-3.0, 3.0))).collect();
        if floating {
            let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            q[3..7].iter_mut().for_each(|x| *x /= norm);
        }
        let [v, tau] = [0; 2].map(|_| (0..nv).map(|_| rng.uniform((-4.0, 4.0))).collect::<Vec<f64>>());
        let args = Arguments {
            q: &q,
            qd: &v,
            tau: &tau,
            ..Arguments::default()
        };
        let value = |name: &str| traced.evaluate_with(name, &args).expect(name);
        let system = value("contact_system");
        let matrices = value("contact_matrices");
        let delassus = value("contact_delassus");
        // The parts in their order: J, M⁻¹ Jᵀ, K, then the drift and the free acceleration.
        let (jacobian, rest) = system.split_at(nc * nv);
        let (response, rest) = rest.split_at(nv * nc);
        let (k, rest) = rest.split_at(nc * nc);
        let (drift, free) = rest.split_at(nc);
        assert_eq!(
            &system[..matrices.len()],
            matrices.as_slice(),
            "{}",
            what("matrices")
        );
        assert_eq!(k, delassus.as_slice(), "{}", what("K alone"));
        assert_eq!(jacobian, value("contact_jacobian").as_slice(), "{}", what("J"));
        assert_eq!(
            response,
            value("contact_response").as_slice(),
            "{}",
            what("M⁻¹ Jᵀ")
        );
        assert_eq!(drift, value("contact_drift").as_slice(), "{}", what("drift"));
        assert_eq!(
            free,
            value("forward_dynamics").as_slice(),
            "{}",
            what("free acceleration")
        );
        let k = DMatrix::from_column_slice(nc, nc, k);
        assert_eq!(k, k.transpose(), "{}", what("K symmetric"));
        let product =
            DMatrix::from_column_slice(nc, nv, jacobian) * DMatrix::from_column_slice(nv, nc, response);
        assert_close(&what("K = J M⁻¹ Jᵀ"), &k, &product, TOL);
        let parts = SystemParts {
            jacobian: DMatrix::from_column_slice(nc, nv, jacobian),
            response: DMatrix::from_column_slice(nv, nc, response),
            delassus: k,
            drift: DVector::from_column_slice(drift),
            free: DVector::from_column_slice(free),
        };
        check_solves(&traced, &q, &v, &tau, &parts, &mut rng, &what);
    }
}

/// The parts of `contact_system` at one state.
struct SystemParts {
    jacobian: DMatrix<f64>,
    response: DMatrix<f64>,
    delassus: DMatrix<f64>,
    drift: DVector<f64>,
    free: DVector<f64>,
}

/// The one-call solves at the state `(q, v, τ)` against their equations, with random targets,
/// warm starts and coefficients.
fn check_solves(
    traced: &dyngen_codegen::internals::generate::SymbolicRobot,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    parts: &SystemParts,
    rng: &mut SplitMix64,
    what: &dyn Fn(&str) -> String,
) {
    let (nc, nv) = parts.jacobian.shape();
    let scale = parts.delassus.diagonal().amax();
    let target: Vec<f64> = (0..nc).map(|_| rng.uniform((-2.0, 2.0))).collect();
    let start: Vec<f64> = (0..nc).map(|_| rng.uniform((-5.0, 5.0))).collect();
    let [kd, mu, restitution, damping] = [
        rng.uniform((0.0, 10.0)),
        0.1 * scale * rng.uniform((0.5, 1.0)),
        rng.uniform((0.0, 1.0)),
        0.1 * scale * rng.uniform((0.5, 1.0)),
    ];
    let args = Arguments {
        q,
        qd: v,
        tau,
        target: &target,
        forces: &start,
        coefficients: &[
            (Coefficient::VelocityGain, kd),
            (Coefficient::Regularisation, mu),
            (Coefficient::Restitution, restitution),
            (Coefficient::Damping, damping),
        ],
        ..Arguments::default()
    };
    let value = |name: &str| traced.evaluate_with(name, &args).expect(name);
    let v = DVector::from_column_slice(v);
    let velocity = &parts.jacobian * &v;
    let regularised = &parts.delassus + DMatrix::identity(nc, nc) * mu;
    let column = |x: &[f64]| DMatrix::from_column_slice(x.len(), 1, x);
    // A step's outputs: a, λ, the λ before, K, the pivots, rhs.
    let check_step =
        |name: &str, base: &DVector<f64>, rhs: &DVector<f64>, start: &DVector<f64>, steps: usize| {
            let out = value(name);
            let (a, rest) = out.split_at(nv);
            let (forces, rest) = rest.split_at(nc);
            let (previous, rest) = rest.split_at(nc);
            let (delassus, rest) = rest.split_at(nc * nc);
            let (pivots, given_rhs) = rest.split_at(nc);
            assert_close(
                &what(&format!("{name}: rhs")),
                &column(given_rhs),
                &column(rhs.as_slice()),
                SOLVE_TOL,
            );
            assert_eq!(
                delassus,
                parts.delassus.as_slice(),
                "{}",
                what(&format!("{name}: K"))
            );
            let mut expected = vec![start.clone()];
            for _ in 0..steps {
                let last = expected.last().expect("the start");
                let next = regularised
                    .clone()
                    .lu()
                    .solve(&(rhs + last * mu))
                    .expect("K + μ I regular");
                expected.push(next);
            }
            let forces_expected = &expected[steps];
            assert_close(
                &what(&format!("{name}: λ")),
                &column(forces),
                &column(forces_expected.as_slice()),
                SOLVE_TOL,
            );
            assert_close(
                &what(&format!("{name}: λ before")),
                &column(previous),
                &column(expected[steps - 1].as_slice()),
                SOLVE_TOL,
            );
            let a_expected = base + &parts.response * forces_expected;
            assert_close(
                &what(&format!("{name}: a")),
                &column(a),
                &column(a_expected.as_slice()),
                SOLVE_TOL,
            );
            let product: f64 = pivots.iter().product();
            let determinant = regularised.determinant();
            assert!(
                (product - determinant).abs() <= SOLVE_TOL * determinant.abs(),
                "{}: {product} against {determinant}",
                what(&format!("{name}: the pivots' product"))
            );
        };
    let rhs =
        DVector::from_column_slice(&target) - &parts.drift - &velocity * kd - &parts.jacobian * &parts.free;
    let start = DVector::from_column_slice(&start);
    check_step("contact_solve", &parts.free, &rhs, &start, 1);
    check_step("contact_proximal_solve", &parts.free, &rhs, &start, 4);
    let impact = -(1.0 + restitution) * &velocity;
    check_step("contact_impulse", &v, &impact, &DVector::zeros(nc), 1);
    let forward = &parts.free + &parts.response * &start;
    assert_close(
        &what("contact_forward_dynamics"),
        &column(&value("contact_forward_dynamics")),
        &column(forward.as_slice()),
        SOLVE_TOL,
    );
    let out = value("contact_inertia");
    let (inertia, rest) = out.split_at(nc * nc);
    let (pivots, diagonal) = rest.split_at(nc);
    let damped = &parts.delassus + DMatrix::identity(nc, nc) * damping;
    let identity = DMatrix::from_column_slice(nc, nc, inertia) * &damped;
    assert_close(
        &what("(K + ε I)⁻¹ (K + ε I)"),
        &identity,
        &DMatrix::identity(nc, nc),
        SOLVE_TOL,
    );
    assert_eq!(
        diagonal,
        parts.delassus.diagonal().as_slice(),
        "{}",
        what("K's diagonal")
    );
    let (product, determinant) = (pivots.iter().product::<f64>(), damped.determinant());
    assert!(
        (product - determinant).abs() <= SOLVE_TOL * determinant.abs(),
        "{}",
        what("contact_inertia: the pivots' product")
    );
}

fn robot(name: &str) -> Model {
    let path = workspace_root().join("robots").join(format!("{name}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

#[test]
fn solo12_on_four_point_feet() {
    check("solo12", &robot("solo12"), true, 20);
}

#[test]
fn a_chain_holding_its_tool_and_a_point_halfway_up() {
    let panda = robot("panda");
    let contacts = vec![
        Contact::at(
            &panda,
            "panda_hand_tcp",
            ContactKind::Point,
            ReferenceFrame::LocalWorldAligned,
        )
        .unwrap(),
        Contact::at(&panda, "panda_link4", ContactKind::Point, ReferenceFrame::Local).unwrap(),
    ];
    check("panda", &panda.with_contacts(contacts).unwrap(), false, 20);
}

#[test]
fn loops_and_dependent_rows() {
    for name in ["two_branches", "four_bar"] {
        let fx = crate::loop_closures::fixture(name);
        for (k, _) in fx["sets"].as_array().unwrap().iter().enumerate() {
            let loaded = crate::loop_closures::load(name, &fx);
            let contacts = common::floating_fixture::contacts(&loaded.model, &fx["sets"][k]);
            let model = loaded.model.with_contacts(contacts).unwrap();
            check(&format!("{name} set {k}"), &model, false, 10);
        }
    }
}
