//! Base parameters of floating-base robots: their number against the rank of regressors stacked
//! by others (Pinocchio 4.1's for the quadruped; states of the tests' own generator for random
//! trees) and against the count that theory gives for generic geometry, `Y_b θ_b = Y θ` for any
//! θ, and the representative parameters (every folded one 0) giving the dynamics of the
//! description: what the generated code is traced with. The traced and compiled base regressors
//! are checked against Pinocchio in `floating_reference.rs` and `generated_floating.rs`.
//!
//! `cargo test -p dyngen-codegen --test suite floating_base_parameters:: -- --nocapture` prints the
//! counts and the worst errors.

use dyngen_testkit as common;

use common::fixture::matrix;
use common::random_model::{arb_floating_model, deterministic_runner, random_floating_sample, SplitMix64};
use common::{floating_fixture, scaled_rank, workspace_root};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_codegen::model::{from_xyz_rpy, Joint, JointKind, Model};
use nalgebra::{DMatrix, Vector3};
use proptest::test_runner::TestCaseError;
use std::cell::Cell;

/// `Y_b θ_b` against `Y θ`, and the representative parameters' dynamics against the
/// description's, relative to the largest entry of the row (worst seen: 9e-14 and 2.6e-12).
const TOL: f64 = 1e-10;

/// The count a floating tree has when no two joint axes are specially placed: the base body's
/// ten, then per revolute joint seven (its body's mass, first moment along the axis and inertia
/// about the axis fold into its parent), per prismatic joint four (the body turns with its
/// parent, so its whole rotational inertia folds).
fn generic_count(model: &Model) -> usize {
    10 + (model.joints().iter())
        .map(|j| match j.kind {
            JointKind::Revolute => 7,
            JointKind::Prismatic => 4,
        })
        .sum::<usize>()
}

/// The floating regressor (Slotine–Li form, `v_r ≠ ν`) stacked at `count` random samples of the
/// tests' own generator, from `first_seed` on: other states than the selection's.
fn fresh_stack(model: &Model, first_seed: u64, count: u64) -> DMatrix<f64> {
    let dynamics = FloatingDynamics::new(model).expect("a floating model");
    let blocks: Vec<DMatrix<f64>> = (first_seed..first_seed + count)
        .map(|seed| {
            let s = random_floating_sample(model, seed);
            let state = dynamics.state(&s.q).expect("a unit quaternion");
            dynamics.regressor(&state, &s.v, &s.vr, &s.ar)
        })
        .collect();
    let nv = model.nv();
    DMatrix::from_fn(nv * blocks.len(), blocks[0].ncols(), |i, j| {
        blocks[i / nv][(i % nv, j)]
    })
}

/// Largest error of `actual` against `expected` row by row, each relative to that row's largest
/// entry (at least `floor`): a light link's row is not hidden behind the base's.
fn row_error(actual: &DMatrix<f64>, expected: &DMatrix<f64>, floor: f64) -> f64 {
    (0..expected.nrows())
        .map(|r| {
            let scale = expected.row(r).amax().max(floor);
            (actual.row(r) - expected.row(r)).amax() / scale
        })
        .fold(0.0, f64::max)
}

fn column(x: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(x.len(), 1, x)
}

#[test]
fn the_quadrupeds_count_is_the_rank_of_pinocchios_regressor() {
    let model = load(&workspace_root().join("robots/solo12.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let base = BaseParameterSet::compute(&model);
    let fx = floating_fixture::load("solo12");
    let blocks: Vec<DMatrix<f64>> = (fx["states"].as_array().unwrap().iter())
        .map(|st| matrix(&st["Y"]))
        .collect();
    let nv = model.nv();
    let stacked = DMatrix::from_fn(nv * blocks.len(), blocks[0].ncols(), |i, j| {
        blocks[i / nv][(i % nv, j)]
    });
    let (rank, s) = scaled_rank(&stacked);
    eprintln!(
        "solo12: {} base parameters of {}; Pinocchio's stacked regressor ({} × {}) has rank {rank} \
         (σ_{rank}/σ_1 = {:.1e}, σ_{}/σ_1 = {:.1e})",
        base.count(),
        base.standard_count,
        stacked.nrows(),
        stacked.ncols(),
        s[rank - 1] / s[0],
        rank + 1,
        s.get(rank).map_or(0.0, |x| x / s[0]),
    );
    assert_eq!(base.count(), rank);
    assert_eq!(base.diagnostics.svd_rank, rank);
    assert_eq!(base.count(), generic_count(&model), "10 + 7 per revolute joint");
    // Parents come first: the base body's mass absorbs every body's.
    assert!(
        base.names[0].starts_with("m[base_link] + m[FL_SHOULDER]"),
        "{}",
        base.names[0]
    );
}

#[test]
fn the_humanoids_count_is_the_rank_at_fresh_states() {
    let path = workspace_root()
        .join("codegen/tests/data/example-robot-data")
        .join("g1_description/g1_29dof_rev_1_0.urdf");
    let options = dyngen_codegen::description::Choices {
        floating_base: true,
        ..Default::default()
    };
    let model = dyngen_codegen::description::load_with(&path, &options)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let base = BaseParameterSet::compute(&model);
    let (rank, _) = scaled_rank(&fresh_stack(&model, 7000, 12));
    eprintln!(
        "g1: {} base parameters of {}, rank at fresh states {rank}, generic count {}",
        base.count(),
        base.standard_count,
        generic_count(&model)
    );
    assert_eq!(base.count(), rank);
    // Its tilted joint frames leave no two axes specially placed.
    assert_eq!(base.count(), generic_count(&model));
}

/// Random floating trees (1–6 joints, light links, heavy tools, bases of 0.1–100 kg): the count
/// is the rank at fresh states and at most the generic count; `Y_b θ_b = Y θ` for a random θ;
/// and the representative parameters give the description's `τ`, `D`, `D⁻¹`, centre of mass,
/// `A_g` and `Ȧ_g ν`.
#[test]
fn random_floating_trees() {
    let worst = [Cell::new(0.0f64), Cell::new(0.0f64)];
    let result = deterministic_runner(48).run(&arb_floating_model(6), |model| {
        let base = BaseParameterSet::compute(&model);
        let (rank, _) = scaled_rank(&fresh_stack(&model, 9000, 6));
        proptest::prop_assert_eq!(base.count(), rank, "{:?}", base.diagnostics);
        proptest::prop_assert_eq!(base.diagnostics.svd_rank, base.count());
        proptest::prop_assert!(base.count() <= generic_count(&model));
        let description = FloatingDynamics::new(&model).unwrap();
        let mut rng = SplitMix64::new(base.count() as u64);
        let theta: Vec<f64> = (0..base.standard_count)
            .map(|_| rng.uniform((-1.0, 1.0)))
            .collect();
        let theta_b = column(&base.base_parameters(&theta));
        let representative = base.representative(&description.parameters());
        let folded = FloatingDynamics::with_parameters(&model, &representative).unwrap();
        for seed in 0..3 {
            let sample = random_floating_sample(&model, 500 + seed);
            let s = description.state(&sample.q).unwrap();
            let y = description.regressor(&s, &sample.v, &sample.vr, &sample.ar);
            let y_theta = &y * column(&theta);
            let err = row_error(
                &(base.base_regressor(&y) * &theta_b),
                &y_theta,
                1e-12 * y_theta.amax(),
            );
            worst[0].set(worst[0].get().max(err));
            proptest::prop_assert!(err <= TOL, "Y_b θ_b vs Y θ: {err:.3e}");
            let pairs: [(&str, DMatrix<f64>, DMatrix<f64>); 6] = [
                (
                    "τ",
                    column(folded.inverse_dynamics(&s, &sample.v, &sample.a).as_slice()),
                    column(description.inverse_dynamics(&s, &sample.v, &sample.a).as_slice()),
                ),
                ("D", folded.mass_matrix(&s), description.mass_matrix(&s)),
                (
                    "D⁻¹",
                    folded.mass_matrix_inverse(&s),
                    description.mass_matrix_inverse(&s),
                ),
                (
                    "com",
                    column(folded.center_of_mass(&s).as_slice()),
                    column(description.center_of_mass(&s).as_slice()),
                ),
                (
                    "A_g",
                    folded.centroidal_momentum_matrix(&s).2,
                    description.centroidal_momentum_matrix(&s).2,
                ),
                (
                    "Ȧ_g ν",
                    column(folded.centroidal_bias(&s, &sample.v).as_slice()),
                    column(description.centroidal_bias(&s, &sample.v).as_slice()),
                ),
            ];
            for (what, actual, expected) in pairs {
                let err = row_error(&actual, &expected, 1e-12 * expected.amax());
                worst[1].set(worst[1].get().max(err));
                proptest::prop_assert!(err <= TOL, "representative {what}: {err:.3e}");
            }
        }
        Ok::<(), TestCaseError>(())
    });
    eprintln!(
        "random floating trees: Y_b θ_b vs Y θ {:.1e}, representative dynamics {:.1e} (tol {TOL:.0e})",
        worst[0].get(),
        worst[1].get()
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// With every joint axis and joint frame in general position (no parallel, intersecting or
/// perpendicular axes), the count is exactly the generic one, on trees of random shape.
#[test]
fn generic_geometry_gives_the_generic_count() {
    let result = deterministic_runner(32).run(&arb_floating_model(6), |model| {
        let generic = in_general_position(&model, model.joints().len() as u64);
        let base = BaseParameterSet::compute(&generic);
        proptest::prop_assert_eq!(base.count(), generic_count(&generic), "{:?}", base.diagnostics);
        Ok::<(), TestCaseError>(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// `model` with every joint's axis uniform on the sphere and its frame at a general rotation
/// and offset (the tree, the bodies and the base unchanged).
fn in_general_position(model: &Model, seed: u64) -> Model {
    let mut rng = SplitMix64::new(seed ^ 0x6E4E_7A11);
    let joints: Vec<Joint> = (model.joints().iter())
        .map(|j| {
            let axis = loop {
                let a = Vector3::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
                if a.norm() > 0.2 && a.norm() <= 1.0 {
                    break a.normalize();
                }
            };
            let xyz = [0; 3].map(|_| rng.uniform((-0.3, 0.3)));
            let rpy = [0; 3].map(|_| rng.uniform((-3.0, 3.0)));
            Joint {
                axis,
                origin: from_xyz_rpy(xyz, rpy),
                ..j.clone()
            }
        })
        .collect();
    Model::new(
        model.name(),
        joints,
        model.bodies().to_vec(),
        model.gravity(),
        model.frames()[0].clone(),
    )
    .and_then(|m| m.with_floating_base(model.floating_base().unwrap().clone()))
    .expect("the same tree in general position")
}

#[test]
fn computation_is_deterministic() {
    let model = load(&workspace_root().join("robots/solo12.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(
        BaseParameterSet::compute(&model),
        BaseParameterSet::compute(&model)
    );
}
