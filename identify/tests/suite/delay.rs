//! A delay of the torque channel behind the positions, searched with the parameters: a delay
//! of 3 samples is found exactly, and the parameters are then those of the same samples
//! without the delay.

use crate::common;

use common::{arm7_noise, arm7_nominal, arm7_truth};
use dyngen_identify::{
    identify, measure, FourierTrajectory, IdentifyOptions, Observation, Samples, TrajectoryLimits,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};

const DELAY: usize = 3;

/// The samples `from..to` of `samples`.
fn slice(samples: &Samples, from: usize, to: usize) -> Samples {
    let cut = |v: &Option<Vec<Vec<f64>>>| v.as_ref().map(|v| v[from..to].to_vec());
    Samples {
        time: samples.time[from..to].to_vec(),
        q: samples.q[from..to].to_vec(),
        qd: cut(&samples.qd),
        qdd: cut(&samples.qdd),
        tau: cut(&samples.tau),
        ..Samples::default()
    }
}

/// arm7 with every joint term, 10 s at 100 Hz with noisy torques; the log as a logger with a
/// delay writes it: each line's torques are those of the motion `DELAY` lines before.
#[test]
fn a_torque_delay_of_three_samples_is_found_and_undone() {
    let (truth, nominal) = (arm7_truth(), arm7_nominal());
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, 6);
    t.fit_into(&limits);
    for exact in [true, false] {
        let measured = measure(&truth, &t, 10.0, 100.0, &arm7_noise(&truth), 2, exact);
        let n = measured.len();
        // Line i: the motion of sample i + DELAY, the torques of sample i.
        let mut delayed = slice(&measured, DELAY, n);
        delayed.time = measured.time[..n - DELAY].to_vec();
        delayed.tau = measured.tau.as_ref().map(|tau| tau[..n - DELAY].to_vec());

        let searched = IdentifyOptions {
            max_delay: Some(10),
            ..IdentifyOptions::default()
        };
        let found = identify(&nominal, &delayed, &searched).expect("identified");
        let search = found.delay.as_ref().expect("searched");
        println!(
            "exact derivatives {exact}: Σ ln σ_j per delay {:?}",
            search
                .criterion
                .iter()
                .map(|(d, c)| format!("{d}: {c:.2}"))
                .collect::<Vec<_>>()
        );
        assert_eq!(search.samples, DELAY as f64);
        assert_eq!(search.criterion.len(), 21);
        println!(
            "ln of the likelihood ratio to the next best: {:.1}",
            search.log_likelihood_margin()
        );
        assert!(search.log_likelihood_margin() > dyngen_identify::DELAY_MARGIN);

        // The same samples without the delay. With exact derivatives: the motions of lines
        // 0..n − 2·DELAY of the delayed log, whose torques are lines DELAY..n − DELAY. With
        // derivatives by the filter, which drops its transients at each end of the log it is
        // given: the motions of the whole delayed log, whose kept samples end early enough
        // for their torques to be in it.
        let end = if exact { n - DELAY } else { n };
        let undelayed = slice(&measured, DELAY, end);
        let without = IdentifyOptions::default();
        let reference = identify(&nominal, &undelayed, &without).expect("identified");
        let (a, b) = (&found.base, &reference.base);
        let mut worst = 0.0f64;
        assert_eq!(found.samples_used, reference.samples_used);
        for k in 0..a.theta_b.len() {
            let difference = (a.theta_b[k] - b.theta_b[k]).abs() / b.std_dev[k];
            worst = worst.max(difference);
            assert!(
                difference <= 1e-9,
                "{}: {} vs {}",
                a.names[k],
                a.theta_b[k],
                b.theta_b[k]
            );
            assert!((a.std_dev[k] / b.std_dev[k] - 1.0).abs() <= 1e-9);
        }
        println!("largest difference from the undelayed estimate: {worst:.1e} σ");

        // The likelihood falls towards the delay and rises after it, on every step.
        for pair in search.criterion.windows(2) {
            let ((d, a), (_, b)) = (pair[0], pair[1]);
            assert_eq!(b < a, d < DELAY as i64, "{:?}", search.criterion);
        }
        if !exact {
            continue;
        }
        // Left uncorrected, the delay costs: the torque noise it leaves is larger.
        let ignored = identify(&nominal, &delayed, &without).expect("identified");
        let ratios: Vec<f64> = (0..7)
            .map(|j| ignored.base.joint_noise[j] / found.base.joint_noise[j])
            .collect();
        println!("noise per joint with the delay ignored / found: {ratios:.2?}");
        assert!(ratios.iter().all(|r| *r > 1.0), "{ratios:?}");
    }
    // Asked of a form that integrates the torques: an error.
    let measured = measure(&truth, &t, 2.0, 100.0, &arm7_noise(&truth), 2, true);
    let windowed = IdentifyOptions {
        max_delay: Some(5),
        observation: Observation::Momentum { window: 0.1 },
        ..IdentifyOptions::default()
    };
    let err = identify(&nominal, &measured, &windowed)
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("a delay is searched in the torque form only"),
        "{err}"
    );
}
