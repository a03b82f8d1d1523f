//! Identification without accelerations, against the torque form on the same simulated data:
//! the energy regressor folds into the torque form's base parameters, both windowed forms
//! recover noise-free parameters, and with a coarse encoder (accelerations differentiated
//! twice from quantised positions) the momentum form is more accurate than the torque form,
//! while the energy form is far worse conditioned than either.

use crate::common;

use common::{arm7, arm7_noise, arm7_nominal, arm7_truth};
use dyngen_identify::{
    identify, measure, with_payload, Identification, IdentifyOptions, Observation, Samples,
};
use dyngen_identify::{
    FourierTrajectory, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY, DEFAULT_WINDOW,
};
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{JointTerms, Model};
use dyngen_runtime::SplitMix64;
use nalgebra::{DVector, Vector3};

fn trajectory(seed: u64) -> FourierTrajectory {
    let limits = TrajectoryLimits::from_model(&arm7_nominal(), DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, seed);
    t.fit_into(&limits);
    t
}

/// Positions rounded to an encoder of `bits` bits per turn of the joint.
fn quantised(samples: &Samples, bits: i32) -> Samples {
    let step = std::f64::consts::TAU / 2f64.powi(bits);
    let mut out = samples.clone();
    for x in out.q.iter_mut().flatten() {
        *x = (*x / step).round() * step;
    }
    out
}

/// Errors of an estimate against the truth: the median and the largest base-parameter error
/// `|θ̂ − θ| / max(|θ|, 1% of the largest |θ|)`, and the RMS torque error on exact data of
/// another trajectory relative to the torques' RMS.
#[derive(Debug)]
struct Errors {
    median: f64,
    largest: f64,
    validation: f64,
}

fn errors(nominal: &Model, truth: &Model, id: &Identification) -> Errors {
    let base = BaseParameterSet::compute(nominal);
    let expected = base.base_parameters(&truth.parameters());
    let scale = expected.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let mut relative: Vec<f64> = id
        .base
        .theta_b
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs() / b.abs().max(0.01 * scale))
        .collect();
    relative.sort_by(f64::total_cmp);
    let validation = trajectory(99);
    let dynamics = NumericDynamics::new(nominal);
    let (estimated, expected) = (
        DVector::from_column_slice(&id.base.theta_b),
        DVector::from_vec(expected),
    );
    let (mut error, mut size) = (0.0, 0.0);
    for k in 0..500 {
        let s = validation.at(k as f64 * 0.02);
        let y = base.base_regressor(&dynamics.regressor(&s.q, &s.qd, &s.qd, &s.qdd));
        let want = &y * &expected;
        error += (&y * &estimated - &want).norm_squared();
        size += want.norm_squared();
    }
    Errors {
        median: relative[relative.len() / 2],
        largest: relative[relative.len() - 1],
        validation: (error / size).sqrt(),
    }
}

fn options(observation: Observation) -> IdentifyOptions {
    IdentifyOptions {
        observation,
        ..IdentifyOptions::default()
    }
}

/// A θ that moves no torque (θ less its base representative) changes no energy between two
/// states, although its energy need not be zero: the potential of the first body's mass and
/// vertical first moment (its axis is vertical) is a constant that only differences remove.
#[test]
fn energy_differences_fold_into_the_base_parameters() {
    let model = arm7_nominal();
    let base = BaseParameterSet::compute(&model);
    let dynamics = NumericDynamics::new(&model);
    let mut rng = SplitMix64::new(4);
    let theta: Vec<f64> = model
        .parameters()
        .iter()
        .map(|p| p + rng.uniform((-1.0, 1.0)))
        .collect();
    let representative = base.representative(&theta);
    let null = DVector::from_iterator(theta.len(), theta.iter().zip(&representative).map(|(a, b)| a - b));
    let theta = DVector::from_vec(theta);
    let t = trajectory(7);
    let energy = |time: f64| {
        let s = t.at(time);
        dynamics.energy_regressor(&s.q, &s.qd)
    };
    let first = energy(0.0).dot(&null);
    let mut worst = 0.0f64;
    for k in 1..50 {
        let e = energy(0.37 * k as f64);
        let change = (&e - energy(0.0)).dot(&theta).abs();
        worst = worst.max((e.dot(&null) - first).abs() / change);
    }
    println!("energy of the null direction {first:.4} J; its largest change {worst:.1e} of the energy's");
    assert!(first.abs() > 1.0, "the constant potential is there: {first}");
    assert!(worst < 1e-12, "{worst}");
}

/// Noise-free data with exact velocities: the momentum form recovers the base parameters of
/// arm7 with a payload and every joint term to the trapezoid rule's error; the energy form
/// likewise on the rigid arm (with every joint term, its scaled condition number on this
/// trajectory's exact data is 2.4·10⁶, beyond the 10⁶ least squares accepts).
#[test]
fn windowed_forms_recover_noise_free_parameters() {
    let nominal = arm7_nominal();
    let truth = arm7_truth();
    let samples = measure(&truth, &trajectory(5), 20.0, 500.0, &[0.0; 7], 1, true);
    let momentum = identify(
        &nominal,
        &samples,
        &options(Observation::Momentum {
            window: DEFAULT_WINDOW,
        }),
    )
    .expect("momentum form");
    let m = errors(&nominal, &truth, &momentum);

    let rigid = arm7()
        .with_joint_terms(JointTerms::default())
        .expect("no joint terms");
    let rigid_truth = with_payload(&rigid, 1.5, Vector3::new(0.0, 0.0, 0.05), 0.04);
    let samples = measure(&rigid_truth, &trajectory(5), 20.0, 500.0, &[0.0; 7], 1, true);
    let energy = identify(
        &rigid,
        &samples,
        &options(Observation::Energy {
            window: DEFAULT_WINDOW,
        }),
    )
    .expect("energy form");
    let e = errors(&rigid, &rigid_truth, &energy);
    println!(
        "noise-free: momentum {m:?} (condition number {:.1}); energy, rigid arm7, {e:?} (condition number {:.1})",
        momentum.base.condition_number, energy.base.condition_number
    );
    assert!(m.largest < 1e-3 && m.validation < 1e-5, "{m:?}");
    assert!(e.largest < 1e-2 && e.validation < 1e-4, "{e:?}");
}

/// arm7 with a payload and every joint term, torque noise of 1% of the rated torque, positions
/// from a 14-bit encoder, velocities and accelerations by the default filter (20 Hz) and
/// differences. The torque form's accelerations carry the quantisation noise amplified twice;
/// the momentum form needs velocities only and is more accurate. The energy form has one
/// equation per window instead of one per joint: its condition number is tens of times the
/// others' and its estimate the least accurate.
#[test]
fn coarse_encoder_momentum_beats_differentiated_accelerations() {
    let nominal = arm7_nominal();
    let truth = arm7_truth();
    let exact = measure(&truth, &trajectory(5), 20.0, 500.0, &arm7_noise(&truth), 2, false);
    let samples = quantised(&exact, 14);
    let torque = identify(&nominal, &samples, &options(Observation::Torque)).expect("torque form");
    let momentum = identify(
        &nominal,
        &samples,
        &options(Observation::Momentum {
            window: DEFAULT_WINDOW,
        }),
    )
    .expect("momentum form");
    let energy = identify(
        &nominal,
        &samples,
        &options(Observation::Energy {
            window: DEFAULT_WINDOW,
        }),
    );
    let (t, m) = (
        errors(&nominal, &truth, &torque),
        errors(&nominal, &truth, &momentum),
    );
    println!(
        "14-bit encoder: torque {t:?} (condition number {:.1}); momentum {m:?} (condition number {:.1})",
        torque.base.condition_number, momentum.base.condition_number
    );
    match &energy {
        Ok(energy) => {
            let e = errors(&nominal, &truth, energy);
            println!(
                "energy {e:?} (condition number {:.3e})",
                energy.base.condition_number
            );
            assert!(energy.base.condition_number > 10.0 * torque.base.condition_number);
            assert!(e.validation > t.validation && e.median > t.median, "{e:?}");
        }
        Err(e) => println!("energy: {e}"),
    }
    assert!(m.validation < 0.5 * t.validation, "{m:?} against {t:?}");
    assert!(m.median < t.median, "{m:?} against {t:?}");
}

/// The table of `docs/identification.md`: the three forms over encoder resolutions and filter
/// cutoffs (about five minutes in the test profile):
/// `cargo test -p dyngen-identify --test suite energy:: -- --ignored --nocapture`.
#[test]
#[ignore]
fn encoder_and_filter_sweep() {
    let nominal = arm7_nominal();
    let truth = arm7_truth();
    let exact = measure(&truth, &trajectory(5), 20.0, 500.0, &arm7_noise(&truth), 2, false);
    let forms = [
        Observation::Torque,
        Observation::Momentum { window: 0.02 },
        Observation::Momentum { window: 0.1 },
        Observation::Energy { window: 0.02 },
        Observation::Energy { window: 0.1 },
    ];
    for bits in [20, 16, 14, 12] {
        let samples = quantised(&exact, bits);
        for cutoff in [20.0, 5.0] {
            let mut line = format!("| {bits} | {cutoff} |");
            for observation in forms {
                let options = IdentifyOptions {
                    cutoff,
                    observation,
                    ..IdentifyOptions::default()
                };
                line += &match identify(&nominal, &samples, &options) {
                    Ok(id) => {
                        let e = errors(&nominal, &truth, &id);
                        format!(" {:.3} / {:.2}% |", e.median, 100.0 * e.validation)
                    }
                    Err(_) => " not identifiable |".to_string(),
                };
            }
            println!("{line}");
        }
    }
}
