//! With sensor noise (σ = 1e-4 rad, 1e-3 rad/s, 0.05 N) the adaptive run stays bounded; with
//! online stiffness estimation from a wrong initial stiffness (Remark 3, no stability proof)
//! the estimate converges and the force is held on this scenario.

use dyngen_control::sim::{start_posture, Demo, DemoOptions, NoiseConfig, RunKind, RunStatus, SimConfig};
use dyngen_generated::arm7;

fn demo(options: DemoOptions) -> Demo<arm7::Standard, 7, 70> {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    Demo::new(options, q0).expect("valid demo")
}

#[test]
fn noisy_run_stays_bounded() {
    let d = demo(DemoOptions {
        sim: SimConfig {
            noise: Some(NoiseConfig::REFERENCE),
            ..SimConfig::default()
        },
        ..DemoOptions::default()
    });
    let res = d.run(RunKind::Adaptive, &mut |_| {}).expect("valid controller");
    assert_eq!(res.status, RunStatus::Completed);
    let s = res.summary(d.metrics_from());
    println!("with noise: {s:?}");
    assert!(s.rms_force_error.is_finite() && s.rms_force_error < 1.0, "{s:?}");
    assert!(s.rms_in_plane_error < 1e-3, "{s:?}");
    assert!(s.max_tau < 200.0, "{s:?}");
}

#[test]
fn stiffness_estimate_converges_from_half_the_true_value() {
    let k = 1e4;
    let d = demo(DemoOptions {
        stiffness: k,
        stiffness_estimation: Some((0.5, 20.0)),
        circle_time: 4.0,
        ..DemoOptions::default()
    });
    let res = d.run(RunKind::Adaptive, &mut |_| {}).expect("valid controller");
    assert_eq!(res.status, RunStatus::Completed);
    let first = res.samples.first().expect("samples").stiffness;
    let last = res.samples.last().expect("samples").stiffness;
    let s = res.summary(d.metrics_from());
    println!("k̂: {first} → {last} N/m (true {k}); {s:?}");
    assert!((first - 0.5 * k).abs() < 1e-6);
    assert!((last - k).abs() < 0.01 * k, "k̂ = {last}");
    assert!(s.rms_force_error < 0.05, "{s:?}");
}
