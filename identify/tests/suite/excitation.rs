//! Excitation trajectories: within the limits, analytic derivatives that the filter and
//! differences reproduce, and an optimised condition number well below random coefficients'.

use crate::common;

use common::arm7_nominal;
use dyngen_identify::Samples;
use dyngen_identify::{condition_number, optimise, ExcitationOptions};
use dyngen_identify::{prepare, BaseModel};
use dyngen_identify::{FourierTrajectory, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY};

fn limits() -> TrajectoryLimits {
    TrajectoryLimits::from_model(&arm7_nominal(), DEFAULT_ACCELERATION_PER_VELOCITY)
}

/// Fitted trajectories stay within every limit at every time (not only on the fitting grid),
/// and one limit per joint is nearly reached (the range is used).
#[test]
fn fitted_trajectories_respect_the_limits() {
    let limits = limits();
    for seed in 0..20 {
        let mut t = FourierTrajectory::random(7, 5, 0.1, seed);
        t.fit_into(&limits);
        let times: Vec<f64> = (0..20_000).map(|k| k as f64 * 1e-3).collect();
        assert_eq!(t.check_limits(&limits, &times), Ok(()), "seed {seed}");
        for j in 0..7 {
            let (mut dq, mut v, mut a) = (0.0f64, 0.0f64, 0.0f64);
            for &time in &times[..10_000] {
                let (q, qd, qdd) = t.joint_at(j, time);
                dq = dq.max((q - t.offsets[j]).abs());
                v = v.max(qd.abs());
                a = a.max(qdd.abs());
            }
            let (lo, hi) = limits.position[j];
            let used = (dq / (0.5 * (hi - lo)))
                .max(v / limits.velocity[j])
                .max(a / limits.acceleration[j]);
            assert!(
                used > 0.9,
                "seed {seed}, joint {j}: uses {used:.3} of its binding limit"
            );
        }
    }
}

/// The derivatives of the series against central differences of its own positions, and the
/// filter-and-differences path of the data against the analytic derivatives.
#[test]
fn derivatives_from_positions_match_the_analytic_ones() {
    let mut t = FourierTrajectory::random(7, 5, 0.1, 3);
    t.fit_into(&limits());
    let rate = 500.0;
    let mut samples = Samples {
        tau: Some(Vec::new()),
        ..Samples::default()
    };
    for k in 0..5000 {
        let time = k as f64 / rate;
        samples.time.push(time);
        samples.q.push(t.at(time).q);
        samples.tau.as_mut().expect("tau").push(vec![0.0; 7]);
    }
    let prepared = prepare(&samples, 20.0).expect("uniform samples");
    assert!(prepared.differentiated);
    let (mut worst_v, mut worst_a) = (0.0f64, 0.0f64);
    for (i, &k) in prepared.kept.iter().enumerate() {
        let exact = t.at(samples.time[k]);
        for j in 0..7 {
            worst_v = worst_v.max((prepared.qd[i][j] - exact.qd[j]).abs());
            worst_a = worst_a.max((prepared.qdd[i][j] - exact.qdd[j]).abs());
        }
    }
    println!("worst velocity error {worst_v:.2e} rad/s, acceleration error {worst_a:.2e} rad/s²");
    assert!(worst_v < 1e-4, "velocity error {worst_v}");
    assert!(worst_a < 1e-3, "acceleration error {worst_a}");
}

/// The optimised excitation's condition number is at most half the random coefficients'
/// (the acceptance threshold), with a short search.
#[test]
fn optimised_excitation_is_better_conditioned_than_random() {
    let nominal = arm7_nominal();
    let base = BaseModel::new(&nominal);
    let limits = limits();
    let options = ExcitationOptions {
        samples: 100,
        starts: 4,
        iterations: 60,
        ..ExcitationOptions::default()
    };
    let e = optimise(&base, &limits, &options);
    println!(
        "condition number {:.2}, random {:.2}",
        e.condition_number, e.random_condition_number
    );
    assert!(e.condition_number <= 0.5 * e.random_condition_number);
    // The number reported is the trajectory's, recomputed independently of the search.
    let again = condition_number(&base, &e.trajectory, options.samples);
    assert!((again - e.condition_number).abs() <= 1e-9 * again);
    let times: Vec<f64> = (0..10_000).map(|k| k as f64 * 1e-3).collect();
    assert_eq!(e.trajectory.check_limits(&limits, &times), Ok(()));
}
