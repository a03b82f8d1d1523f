//! A payload identified on arm7 identified beforehand: from 10 s of positions and torques,
//! from a wrist force/torque sensor alone, and from both; the body regressor against the
//! inverse dynamics; what a payload that is not a physical body and a bad request become.

use crate::common;

use common::{arm7, arm7_joint_values, arm7_noise, arm7_nominal};
use dyngen_identify::{
    identify, identify_payload, measure, measure_wrench, with_body_at, with_joint_terms, FourierTrajectory,
    IdentifyOptions, PayloadData, PayloadEstimate, PayloadOptions, Samples, TrajectoryLimits,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};
use dyngen_model::description::load_yaml_str;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{Inertia, Model};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::path::Path;

const RATE: f64 = 500.0;
/// A force/torque sensor's noise per axis (N, N·m) and a zero offset it has drifted to.
const SENSOR_NOISE: [f64; 6] = [0.05, 0.05, 0.08, 0.003, 0.003, 0.002];
const SENSOR_OFFSET: [f64; 6] = [1.5, -0.8, 2.0, 0.05, -0.03, 0.02];

fn trajectory(seed: u64) -> FourierTrajectory {
    let limits = TrajectoryLimits::from_model(&arm7_nominal(), DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, seed);
    t.fit_into(&limits);
    t
}

/// The real arm (joint friction and armature, no payload).
fn robot() -> Model {
    with_joint_terms(&arm7(), &arm7_joint_values(), None)
}

/// The payload: 2.3 kg, centre of mass off every axis of the flange, an inertia turned away
/// from them (a 12 × 8 × 20 cm box tilted on two axes).
fn payload() -> Inertia {
    let (a, b, c, m) = (0.12f64, 0.08f64, 0.2f64, 2.3);
    let principal =
        Matrix3::from_diagonal(&Vector3::new(b * b + c * c, a * a + c * c, a * a + b * b)) * (m / 12.0);
    let turn = Rotation3::from_euler_angles(0.4, -0.3, 0.2).into_inner();
    Inertia {
        mass: m,
        com: Vector3::new(0.015, -0.02, 0.09),
        inertia_com: turn * principal * turn.transpose(),
    }
}

/// arm7 identified from 30 s of an exciting motion (positions and noisy torques), as a user
/// has it before the payload: its written description, loaded.
fn identified_robot() -> Model {
    let truth = robot();
    let samples = measure(&truth, &trajectory(21), 30.0, RATE, &arm7_noise(&truth), 5, false);
    let id = identify(&arm7_nominal(), &samples, &IdentifyOptions::default()).expect("identified");
    load_yaml_str(&id.yaml("test"), Path::new("identified.yaml"))
        .expect("loads")
        .model
}

/// 10 s of the robot with the payload, along another motion: positions and torques, and the
/// wrist sensor at the flange.
fn payload_data(truth_robot: &Model, seed: u64) -> Samples {
    let truth = with_body_at(truth_robot, "flange", &payload());
    let motion = trajectory(seed);
    let mut samples = measure(&truth, &motion, 10.0, RATE, &arm7_noise(&truth), seed, false);
    samples.wrench = Some(measure_wrench(
        truth_robot,
        &truth,
        "flange",
        &motion,
        10.0,
        RATE,
        &SENSOR_NOISE,
        &SENSOR_OFFSET,
        seed + 1,
    ));
    samples.sensor_frame = Some("flange".into());
    samples
}

fn report(what: &str, p: &PayloadEstimate) -> (f64, f64) {
    let truth = payload();
    let mass_error = (p.mass / truth.mass - 1.0).abs();
    let com_error = (p.com - truth.com).norm();
    println!(
        "{what}: mass {:.4} kg ({:.2}%), centre of mass {:.4?} ({:.2} mm off), inertia error {:.2e} kg·m² (largest entry), consistent adjusted: {}",
        p.mass,
        100.0 * mass_error,
        p.com.as_slice(),
        1e3 * com_error,
        (p.inertia_com - truth.inertia_com).abs().max(),
        p.made_consistent
    );
    (mass_error, com_error)
}

/// Torque RMS error per joint of `model` in units of the noise σ, on a third motion of the
/// robot with the payload.
fn validation(truth_robot: &Model, model: &Model) -> Vec<f64> {
    let truth = with_body_at(truth_robot, "flange", &payload());
    let noise = arm7_noise(&truth);
    let data = measure(&truth, &trajectory(99), 10.0, RATE, &noise, 77, true);
    let dynamics = NumericDynamics::new(model);
    let (qd, qdd, tau) = (
        data.qd.as_ref().expect("qd"),
        data.qdd.as_ref().expect("qdd"),
        data.tau.as_ref().expect("tau"),
    );
    let mut squares = [0.0; 7];
    for k in 0..data.len() {
        let predicted = dynamics.inverse_dynamics(&data.q[k], &qd[k], &qdd[k]);
        for j in 0..7 {
            squares[j] += (tau[k][j] - predicted[j]).powi(2);
        }
    }
    (0..7)
        .map(|j| (squares[j] / data.len() as f64).sqrt() / noise[j])
        .collect()
}

#[test]
fn payload_from_torques_sensor_and_both_on_an_identified_arm() {
    let truth_robot = robot();
    let identified = identified_robot();
    let data = payload_data(&truth_robot, 31);

    let torques = PayloadOptions {
        data: Some(PayloadData::Torques),
        ..PayloadOptions::default()
    };
    let from_torques = identify_payload(&identified, &data, &torques).expect("from torques");
    assert_eq!(from_torques.frame, "flange");
    let (mass, com) = report("torques", &from_torques);
    assert!(mass <= 0.02 && com <= 0.005);
    let rms = validation(&truth_robot, &from_torques.model);
    println!("validation torque RMS / σ per joint: {rms:.3?}");
    assert!(rms.iter().all(|r| *r <= 1.2), "{rms:?}");
    // The description written loads, with the payload in it.
    let yaml = from_torques.yaml("the test's data");
    let loaded = load_yaml_str(&yaml, Path::new("with_payload.yaml"))
        .expect("loads")
        .model;
    let total = |m: &Model| m.bodies().iter().map(|b| b.inertia.mass).sum::<f64>();
    assert!((total(&loaded) - total(&identified) - from_torques.mass).abs() <= 1e-9);

    let sensor = PayloadOptions {
        data: Some(PayloadData::Wrench),
        ..PayloadOptions::default()
    };
    let from_sensor = identify_payload(&identified, &data, &sensor).expect("from the sensor");
    let (mass, com) = report("sensor", &from_sensor);
    assert!(mass <= 0.01 && com <= 0.005);
    let offset = from_sensor.sensor_offset.expect("an offset");
    for c in 0..6 {
        assert!(
            (offset[c] - SENSOR_OFFSET[c]).abs() <= 0.05 * SENSOR_OFFSET[c].abs().max(0.1),
            "{offset:?}"
        );
    }

    let both = identify_payload(&identified, &data, &PayloadOptions::default()).expect("both");
    assert_eq!(both.data, PayloadData::Both);
    let (mass, com) = report("both", &both);
    assert!(mass <= 0.01 && com <= 0.005);
    // The sources agree: the sensor's readings fit a payload to their noise, and fitting them
    // with the torques costs no channel much of its fit alone (the description held is an
    // identified one, not the truth).
    let check = both.sources.as_ref().expect("checked");
    println!(
        "sensor misfit per axis {:.2?}, noise together / alone per channel {:.2?}",
        check.sensor_misfit, check.joint_cost
    );
    assert_eq!(check.disagreement, None);
    assert!(check.sensor_misfit.expect("fitted").iter().all(|r| *r < 1.5));
    assert!(
        check.joint_cost.iter().all(|r| *r < 2.0),
        "{:?}",
        check.joint_cost
    );
    assert!(both.warnings.is_empty(), "{:?}", both.warnings);
}

/// `data` with the sensor's readings changed by `f` (each sample's `[f; m]`).
fn with_wrench(data: &Samples, f: impl Fn([f64; 6]) -> [f64; 6]) -> Samples {
    let mut changed = data.clone();
    for w in changed.wrench.as_mut().expect("a wrench") {
        *w = f(*w);
    }
    changed
}

/// What `identify_payload` says of `data`: the disagreement of an estimate, or the error.
fn verdict(robot: &Model, data: &Samples, from: PayloadData) -> String {
    let options = PayloadOptions {
        data: Some(from),
        ..PayloadOptions::default()
    };
    match identify_payload(robot, data, &options) {
        Ok(p) => {
            let check = p.sources.expect("a sensor is checked");
            println!(
                "{from:?}: masses {:?} (torques) {:?} (sensor), sensor misfit {:.1?}, costs {:.1?}",
                check.mass_from_torques, check.mass_from_wrench, check.sensor_misfit, check.joint_cost
            );
            assert_eq!(p.warnings.first(), check.disagreement.as_ref());
            check.disagreement.unwrap_or_default()
        }
        Err(e) => e.to_string(),
    }
}

/// A sensor that reports the opposite sign, one mounted turned by a quarter turn about its z
/// axis, and one zeroed with the payload on: the first two are one line naming the likely
/// cause, the third (an offset a constant absorbs) is no problem.
#[test]
fn a_flipped_or_turned_sensor_is_named() {
    let robot = robot();
    let data = payload_data(&robot, 61);
    let flipped = with_wrench(&data, |w| w.map(|v| -v));
    let message = verdict(&robot, &flipped, PayloadData::Both);
    assert!(
        message.starts_with("the force/torque sensor and the joint torques disagree: fitted together,")
            && message.contains("likely cause: the sensor's sign")
            && message.contains("negate its six columns"),
        "{message}"
    );
    let message = verdict(&robot, &flipped, PayloadData::Wrench);
    assert!(
        message.contains("the data shows no payload: its estimated mass is -2.3")
            && message.contains("negate its six columns"),
        "{message}"
    );

    // Turned: the columns are the wrench in axes turned by 90° about z.
    let turned = with_wrench(&data, |w| [w[1], -w[0], w[2], w[4], -w[3], w[5]]);
    for from in [PayloadData::Both, PayloadData::Wrench] {
        let message = verdict(&robot, &turned, from);
        assert!(
            message.contains(
                "likely cause: the sensor's frame: its readings are not a wrench in the axes of 'flange'"
            ),
            "{from:?}: {message}"
        );
    }
    let message = verdict(&robot, &turned, PayloadData::Wrench);
    assert!(
        message.starts_with("the force/torque sensor's readings fit no payload: its residuals are"),
        "{message}"
    );

    // Zeroed with the payload on at the first sample: an offset of the payload's weight,
    // which the sensor's offset absorbs; the sources agree.
    let first = data.wrench.as_ref().expect("a wrench")[0];
    let zeroed = with_wrench(&data, |w| std::array::from_fn(|c| w[c] - first[c]));
    let p = identify_payload(&robot, &zeroed, &PayloadOptions::default()).expect("zeroed");
    let check = p.sources.expect("checked");
    assert_eq!(check.disagreement, None);
    assert!(check.offset_force.expect("an offset").norm() > 0.5 * 2.3 * 9.81);
    assert!((p.mass / payload().mass - 1.0).abs() <= 0.01, "{}", p.mass);
}

/// The sensor path's body regressor against the inverse dynamics: with exact data and no
/// noise, the payload comes back to rounding (it is built from `τ_truth − τ_held = Jᵀ w`).
#[test]
fn noise_free_sensor_data_gives_the_payload_exactly() {
    let robot = robot();
    let truth = with_body_at(&robot, "flange", &payload());
    let motion = trajectory(8);
    let mut data = measure(&truth, &motion, 4.0, 100.0, &[0.0; 7], 1, true);
    data.wrench = Some(measure_wrench(
        &robot,
        &truth,
        "flange",
        &motion,
        4.0,
        100.0,
        &[0.0; 6],
        &SENSOR_OFFSET,
        1,
    ));
    data.sensor_frame = Some("flange".into());
    for data_kind in [PayloadData::Wrench, PayloadData::Torques] {
        let options = PayloadOptions {
            data: Some(data_kind),
            ..PayloadOptions::default()
        };
        let p = identify_payload(&robot, &data, &options).expect("identified");
        let truth = payload();
        assert!(
            (p.mass - truth.mass).abs() <= 1e-9 * truth.mass,
            "{data_kind:?}: {}",
            p.mass
        );
        assert!((p.com - truth.com).norm() <= 1e-9, "{data_kind:?}: {}", p.com);
        assert!(
            (p.inertia_com - truth.inertia_com).abs().max() <= 1e-9,
            "{data_kind:?}"
        );
        assert!(!p.made_consistent);
    }
}

/// Re-fitting the joint terms with the payload: from a description whose friction is half
/// the truth's, the re-fitted terms come back near the truth's and the payload as well.
#[test]
fn joint_terms_refitted_beside_the_payload() {
    let truth_robot = robot();
    let half: Vec<_> = arm7_joint_values()
        .into_iter()
        .map(|mut v| {
            v.viscous *= 0.5;
            v.coulomb *= 0.5;
            v
        })
        .collect();
    let held = with_joint_terms(&arm7(), &half, None);
    let data = payload_data(&truth_robot, 41);
    let held_fit = identify_payload(
        &held,
        &data,
        &PayloadOptions {
            data: Some(PayloadData::Torques),
            ..PayloadOptions::default()
        },
    )
    .expect("held");
    let refit = identify_payload(
        &held,
        &data,
        &PayloadOptions {
            data: Some(PayloadData::Torques),
            refit_joint_terms: true,
            ..PayloadOptions::default()
        },
    )
    .expect("refit");
    let (held_mass, _) = report("friction half, held", &held_fit);
    let (refit_mass, refit_com) = report("friction half, re-fitted", &refit);
    assert!(refit_mass <= 0.02 && refit_com <= 0.005);
    assert!(refit_mass < held_mass);
    let terms = refit.joint_terms.expect("re-fitted");
    for (j, (got, want)) in terms.iter().zip(arm7_joint_values()).enumerate() {
        assert!(
            (got.coulomb - want.coulomb).abs() <= 0.15 * want.coulomb,
            "joint {j}: {got:?} vs {want:?}"
        );
    }
}

/// Requests the data cannot answer are errors that say why.
#[test]
fn bad_requests_are_clear_errors() {
    let robot = robot();
    let mut data = payload_data(&robot, 51);
    let err = |options: PayloadOptions, data: &Samples| {
        identify_payload(&robot, data, &options)
            .expect_err("refused")
            .to_string()
    };
    let unknown = PayloadOptions {
        frame: Some("gripper".into()),
        ..PayloadOptions::default()
    };
    let message = err(unknown, &data);
    assert!(
        message.contains("the payload frame 'gripper' is not a frame of the description (its frames: flange"),
        "{message}"
    );
    let elsewhere = PayloadOptions {
        frame: Some("flange".into()),
        ..PayloadOptions::default()
    };
    data.sensor_frame = Some("nowhere".into());
    let message = err(elsewhere, &data);
    assert!(
        message.contains("the sensor frame 'nowhere' is not a frame"),
        "{message}"
    );
    data.wrench = None;
    data.sensor_frame = None;
    let sensor = PayloadOptions {
        data: Some(PayloadData::Wrench),
        ..PayloadOptions::default()
    };
    let message = err(sensor, &data);
    assert!(message.contains("the data has no wrench columns"), "{message}");
}
