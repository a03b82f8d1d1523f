//! The committed generated base regressors: `Y_b θ_b = Y θ = D a + C v + g` for the
//! description's θ and random θ, `Y_b` is the generator's kept columns of `Y`, `θ_b`, the
//! names and the count agree with the generator, and the products an adaptive law takes
//! (`Y θ`, `Yᵀ r` and their base forms, computed without the regressor) equal the regressor's.

use dyngen_testkit as common;

use common::random_model::{random_state, SplitMix64};
use common::{assert_close, column};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::model::Model;
use dyngen_generated::{arm7, panda, panda_rounded, ur5, Arm7, Panda, PandaRounded, Ur5};
use dyngen_runtime::nalgebra::{SMatrix, SVector};
use dyngen_runtime::{Base, BaseParameters, JointTrig, Parameterization};
use std::path::Path;

/// `Y_b θ_b` against `Y θ`, relative (to the largest torque, at least 1).
const TOL: f64 = 1e-10;

/// A kept column of `Y_b` against the same column of `Y`: rounding only.
const KEPT_COLUMN_TOL: f64 = 1e-14;

fn described(robot: &str) -> Model {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../robots")).join(format!("{robot}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// θ with every entry uniform in ±1.
fn random_theta(p: usize, seed: u64) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    (0..p).map(|_| rng.uniform((-1.0, 1.0))).collect()
}

/// Compiled generated code: `Y_b θ_b = Y θ` for the description's θ and random θ at 300 random
/// states, `Y_b` is the kept columns of `Y`, and `θ_b`, names and count agree with the generator.
fn check_generated<R, const N: usize, const P: usize, const B: usize>(robot: &str)
where
    R: BaseParameters<N, P, B>,
    Base<R, P>: Parameterization<N, B>,
{
    let model = described(robot);
    let base = BaseParameterSet::compute(&model);
    assert_eq!(B, base.count(), "{robot}: B");
    assert_eq!(R::BASE_PARAMETER_NAMES.to_vec(), base.names, "{robot}: names");
    assert_eq!(
        <Base<R, P> as Parameterization<N, B>>::NAMES,
        R::BASE_PARAMETER_NAMES
    );
    let thetas: Vec<SVector<f64, P>> = std::iter::once(R::parameters())
        .chain((0..3).map(|k| SVector::from_column_slice(&random_theta(P, 100 + k))))
        .collect();
    for theta in &thetas {
        let theta_b = R::base_parameters(theta);
        let numeric = base.base_parameters(theta.as_slice());
        assert_close(
            &format!("{robot}: generated θ_b vs generator's θ_b"),
            &column(theta_b.as_slice()),
            &column(&numeric),
            1e-14,
        );
    }
    let cols: Vec<usize> = base.columns.clone();
    for seed in 0..300 {
        let s = random_state(&model, 10_000 + seed);
        let t = JointTrig::new(&SVector::<f64, N>::from_column_slice(&s.q));
        let [qd, v, a] = [&s.qd, &s.v, &s.a].map(|x| SVector::<f64, N>::from_column_slice(x));
        let y: SMatrix<f64, N, P> = R::regressor(&t, &qd, &v, &a);
        let y_b: SMatrix<f64, N, B> = R::base_regressor(&t, &qd, &v, &a);
        let via_trait = <Base<R, P> as Parameterization<N, B>>::regressor(&t, &qd, &v, &a);
        assert_eq!(y_b, via_trait);
        // The same graph nodes, but each function fuses its own products into multiply-adds
        // (a product `Y` shares with a folded column stays apart there), so where the build
        // fuses, an entry may round differently in its last bit: equal to rounding, not bit
        // for bit (an unfused build, such as the default test profile, agrees exactly).
        for (k, &c) in cols.iter().enumerate() {
            assert_close(
                &format!("{robot} seed {seed}: Y_b column {k} vs Y column {c}"),
                &column(y_b.column(k).as_slice()),
                &column(y.column(c).as_slice()),
                KEPT_COLUMN_TOL,
            );
        }
        for (i, theta) in thetas.iter().enumerate() {
            let tau = y * theta;
            let tau_b = y_b * R::base_parameters(theta);
            assert_close(
                &format!("{robot} seed {seed} θ #{i}: Y_b θ_b vs Y θ"),
                &column(tau_b.as_slice()),
                &column(tau.as_slice()),
                TOL,
            );
        }
        // The torque form is the same columns of `Y` at `v = q̇`, and `Y_b θ_b = τ`.
        let y_torque: SMatrix<f64, N, P> = R::torque_regressor(&t, &qd, &a);
        let y_b_torque: SMatrix<f64, N, B> = R::base_torque_regressor(&t, &qd, &a);
        assert_close(
            &format!("{robot} seed {seed}: Y(q, q̇, q̇, q̈)"),
            &column(y_torque.as_slice()),
            &column(R::regressor(&t, &qd, &qd, &a).as_slice()),
            TOL,
        );
        for (k, &c) in cols.iter().enumerate() {
            assert_close(
                &format!("{robot} seed {seed}: torque-form Y_b column {k} vs Y column {c}"),
                &column(y_b_torque.column(k).as_slice()),
                &column(y_torque.column(c).as_slice()),
                KEPT_COLUMN_TOL,
            );
        }
        assert_close(
            &format!("{robot} seed {seed}: torque-form Y_b θ_b vs τ"),
            &column((y_b_torque * R::base_parameters(&R::parameters())).as_slice()),
            &column(R::inverse_dynamics(&t, &qd, &a).as_slice()),
            TOL,
        );
        // The products an adaptive law takes, computed without forming either regressor.
        let mut rng = SplitMix64::new(seed);
        let r = SVector::<f64, N>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
        let (theta, theta_b) = (&thetas[1], R::base_parameters(&thetas[1]));
        let (y_theta, y_tr_r) = R::regressor_products(&t, &qd, &v, &a, theta, &r);
        let (y_b_theta, y_b_tr_r) = R::base_regressor_products(&t, &qd, &v, &a, &theta_b, &r);
        for (what, fast, slow) in [
            ("Y θ", y_theta.as_slice(), (y * theta).as_slice().to_vec()),
            ("Yᵀ r", y_tr_r.as_slice(), (y.tr_mul(&r)).as_slice().to_vec()),
            (
                "Y_b θ_b",
                y_b_theta.as_slice(),
                (y_b * theta_b).as_slice().to_vec(),
            ),
            (
                "Y_bᵀ r",
                y_b_tr_r.as_slice(),
                (y_b.tr_mul(&r)).as_slice().to_vec(),
            ),
        ] {
            assert_close(
                &format!("{robot} seed {seed}: {what} without the regressor vs with it"),
                &column(fast),
                &column(&slow),
                TOL,
            );
        }
        let via_trait =
            <Base<R, P> as Parameterization<N, B>>::regressor_products(&t, &qd, &v, &a, &theta_b, &r);
        assert_eq!(via_trait, (y_b_theta, y_b_tr_r));
        if seed == 0 {
            // Y θ with the description's θ is the Slotine–Li torque.
            let sl = R::slotine_li(&t, &qd, &v, &a);
            let tau_b = y_b * R::base_parameters(&R::parameters());
            assert_close(
                &format!("{robot}: Y_b θ_b vs D a + C v + g"),
                &column(tau_b.as_slice()),
                &column(sl.as_slice()),
                TOL,
            );
        }
    }
}

#[test]
fn generated_arm7_base_regressor() {
    check_generated::<Arm7, { arm7::DOF }, { arm7::PARAMETER_COUNT }, { arm7::BASE_PARAMETER_COUNT }>("arm7");
}

#[test]
fn generated_panda_base_regressor() {
    check_generated::<Panda, { panda::DOF }, { panda::PARAMETER_COUNT }, { panda::BASE_PARAMETER_COUNT }>(
        "panda",
    );
}

#[test]
fn generated_panda_rounded_base_regressor() {
    check_generated::<
        PandaRounded,
        { panda_rounded::DOF },
        { panda_rounded::PARAMETER_COUNT },
        { panda_rounded::BASE_PARAMETER_COUNT },
    >("panda_rounded");
}

#[test]
fn generated_ur5_base_regressor() {
    check_generated::<Ur5, { ur5::DOF }, { ur5::PARAMETER_COUNT }, { ur5::BASE_PARAMETER_COUNT }>("ur5");
}
