//! The controlled frame: the controller, the plant and the demo at a named frame of a robot
//! generated with the group `frames` instead of the end-effector. The end-effector chosen by
//! name is the default to the bit; the Panda's flange `panda_link8` (10 cm above the TCP)
//! meets the demo's thresholds as the end-effector does, with the table touched there; an
//! unknown name lists the robot's frames.

use dyngen_control::controller::{frame_named, ConfigError, HybridController, Measurement};
use dyngen_control::sim::{
    rk4_step, simulate, start_posture_for, Demo, DemoOptions, Plant, PlantState, RunKind, RunResult,
    RunStatus, Summary, Surface,
};
use dyngen_generated::{panda, ur5, Panda, Ur5};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{FrameKinematics, JointTrig, Kinematics, Parameterization, RobotFrame};

/// The demo's options with a 0.5 s circle: 3.5 s in all.
fn short() -> DemoOptions {
    DemoOptions {
        circle_time: 0.5,
        ..DemoOptions::default()
    }
}

/// Ticks the default controller and the one given the end-effector by name side by side on
/// the default's closed loop (plant by RK4, torque held): the torques, `θ̂̇` and `θ̂` are the
/// same to the bit at every tick.
fn end_effector_by_name_is_the_default<Z, const N: usize, const M: usize, const T: usize>()
where
    Z: Parameterization<N, M>,
    Z::Robot: FrameKinematics<N>,
{
    let end_effector = <Z::Robot as FrameKinematics<N>>::Frame::ALL[0];
    let q0 = start_posture_for::<Z::Robot, N>(None).expect("start posture");
    let demo = Demo::<Z, N, M, T>::new(short(), q0).expect("valid demo");
    let mut default: HybridController<Z, N, M, T> = demo.controller(RunKind::Adaptive).expect("controller");
    let mut named = demo
        .controller(RunKind::Adaptive)
        .expect("controller")
        .with_controlled_frame(end_effector);
    assert_eq!(default.controlled_frame(), None);
    assert_eq!(named.controlled_frame(), Some(end_effector.name()));
    let dt = demo.options.sim.control_period;
    let mut s = PlantState {
        q: q0,
        qd: SVector::zeros(),
    };
    let steps = (demo.scenario.duration() / dt).round() as usize;
    let mut in_contact = 0;
    let mut tau = SVector::zeros();
    for k in 0..steps {
        let t = k as f64 * dt;
        let force = demo.plant.contact_force(&s, &tau).expect("compliant");
        in_contact += usize::from(force.norm() > 0.0);
        let m = Measurement {
            q: s.q,
            qd: s.qd,
            force,
        };
        let d = demo.scenario.desired(t);
        let a = default.tick(&m, &d, dt).expect("tick");
        let b = named.tick(&m, &d, dt).expect("tick");
        tau = a.tau;
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a.tau.as_slice()), bits(b.tau.as_slice()), "τ at t = {t}");
        assert_eq!(
            bits(a.theta_hat_dot.as_slice()),
            bits(b.theta_hat_dot.as_slice()),
            "θ̂̇ at t = {t}"
        );
        assert_eq!(
            bits(default.theta_hat().as_slice()),
            bits(named.theta_hat().as_slice())
        );
        let h = dt / 5.0;
        for sub in 0..5 {
            s = rk4_step(t + sub as f64 * h, &s, h, |_, x| demo.plant.derivative(x, &a.tau))
                .expect("plant step");
        }
    }
    // Not a free-space-only comparison: most of the run presses on the table.
    assert!(in_contact > steps / 2, "{in_contact} of {steps} ticks in contact");

    // The demo built at the end-effector by name logs the same run to the bit (tick times
    // aside).
    let by_name =
        Demo::<Z, N, M, T>::new_at_frame(short(), q0, end_effector).expect("valid demo at the end-effector");
    let strip = |r: &RunResult| {
        assert_eq!(r.status, RunStatus::Completed);
        r.samples
            .iter()
            .map(|x| {
                [
                    x.t,
                    x.force,
                    x.true_force,
                    x.force_error,
                    x.in_plane_error,
                    x.orientation_error,
                    x.null_error,
                    x.lyapunov,
                    x.theta_error,
                    x.tau_max,
                    x.damping,
                ]
                .map(f64::to_bits)
            })
            .collect::<Vec<_>>()
    };
    let a = demo.run(RunKind::Adaptive, &mut |_| {}).expect("run");
    let b = by_name.run(RunKind::Adaptive, &mut |_| {}).expect("run");
    assert!(strip(&a) == strip(&b), "the logged runs differ");
}

/// (1) The end-effector chosen by name gives the default's torques, bit for bit.
#[test]
fn the_end_effector_by_name_gives_the_default_torques_bit_for_bit() {
    end_effector_by_name_is_the_default::<panda::Base, 7, { panda::BASE_PARAMETER_COUNT }, 3>();
    end_effector_by_name_is_the_default::<panda::Base, 7, { panda::BASE_PARAMETER_COUNT }, 6>();
    end_effector_by_name_is_the_default::<ur5::Standard, 6, { ur5::PARAMETER_COUNT }, 5>();
}

/// The Panda's demo with its flange `panda_link8` as the controlled frame, and its start.
fn flange_demo() -> (
    SVector<f64, 7>,
    Demo<panda::Base, 7, { panda::BASE_PARAMETER_COUNT }, 3>,
) {
    let q0 = start_posture_for::<Panda, 7>(None).expect("start posture");
    let demo = Demo::new_at_frame(DemoOptions::default(), q0, panda::Frame::PandaLink8).expect("valid demo");
    (q0, demo)
}

fn run_at_link8(kind: RunKind) -> (Summary, RunResult) {
    let (_, demo) = flange_demo();
    let res = demo.run(kind, &mut |_| {}).expect("valid controller");
    assert_eq!(res.status, RunStatus::Completed, "{kind:?}");
    let s = res.summary(demo.metrics_from());
    println!("panda_link8, {kind:?}: {s:?}");
    (s, res)
}

/// RMS of `f` over `from ≤ t < to`.
fn rms(res: &RunResult, from: f64, to: f64, f: fn(&dyngen_control::sim::Sample) -> f64) -> f64 {
    let w: Vec<f64> = res
        .samples
        .iter()
        .filter(|s| s.t >= from && s.t < to)
        .map(|s| f(s).powi(2))
        .collect();
    (w.iter().sum::<f64>() / w.len() as f64).sqrt()
}

/// (2) The Panda's flange `panda_link8` as the controlled frame, on the demo's scenario (press
/// on the table with the flange, then a circle): the thresholds of the end-effector's test
/// (`closed_loop_thresholds.rs`) hold, adaptation off is far worse, and the adaptive run's force
/// and in-plane errors go down from the first 0.5 s to the last 4 s.
#[test]
fn a_controller_of_the_panda_flange_converges_in_contact() {
    let (adaptive, res) = run_at_link8(RunKind::Adaptive);
    let (off, ..) = run_at_link8(RunKind::AdaptationOff);
    let (known, ..) = run_at_link8(RunKind::KnownParameters);
    assert!(adaptive.rms_force_error <= 0.02, "{adaptive:?}");
    assert!(adaptive.rms_in_plane_error <= 1e-5, "{adaptive:?}");
    assert!(off.rms_force_error >= 100.0 * adaptive.rms_force_error, "{off:?}");
    assert!(
        off.rms_in_plane_error >= 10.0 * adaptive.rms_in_plane_error,
        "{off:?}"
    );
    assert!(known.rms_force_error <= adaptive.rms_force_error);
    assert!(adaptive.final_null_error < 1e-3, "{}", adaptive.final_null_error);
    // Converging: from the first 0.5 s (the unknown payload pulls the flange off its path
    // while the estimate adapts) to the last 4 s, and `V` lower at the end than at the start.
    let end = res.samples.last().expect("samples").t + 1e-9;
    let early_force = rms(&res, 0.0, 0.5, |s| s.force_error);
    let early_plane = rms(&res, 0.0, 0.5, |s| s.in_plane_error);
    let late_force = rms(&res, end - 4.0, end, |s| s.force_error);
    let late_plane = rms(&res, end - 4.0, end, |s| s.in_plane_error);
    println!("force {early_force:.3e} → {late_force:.3e} N, in-plane {early_plane:.3e} → {late_plane:.3e} m");
    assert!(late_force < 0.1 * early_force);
    assert!(late_plane < 0.75 * early_plane);
    let first = res.samples.first().expect("samples");
    assert!(res.samples.last().expect("samples").lyapunov < first.lyapunov);
    // Pressing with the flange: the true contact force is the target at the end.
    let last = res.samples.last().expect("samples");
    assert!((last.true_force - 10.0).abs() < 0.1, "{last:?}");
}

/// The demo at the flange: the table is under the flange (the TCP, 10 cm below it, would be
/// deep in the table), the plant touches it there and the controllers control it.
#[test]
fn the_demo_at_a_frame_puts_the_table_under_that_frame() {
    let (q0, demo) = flange_demo();
    let t = JointTrig::new(&q0);
    let flange = Panda::frame_pose(panda::Frame::PandaLink8, &t).translation;
    let tcp = Panda::forward_kinematics(&t).translation;
    let surface = demo.plant.contact.point().z;
    assert!((flange.z - surface - DemoOptions::default().start_height).abs() < 1e-12);
    assert!(tcp.z < surface - 0.05, "TCP {tcp:?}, surface {surface}");
    assert_eq!(demo.controlled_frame(), Some("panda_link8"));
    assert_eq!(demo.plant.contact_frame(), Some("panda_link8"));
    let c = demo.controller(RunKind::Adaptive).expect("controller");
    assert_eq!(c.controlled_frame(), Some("panda_link8"));
    // Above the table at the start: no contact force.
    let rest = PlantState::at_rest(q0);
    let force = demo
        .plant
        .contact_force(&rest, &SVector::zeros())
        .expect("compliant");
    assert_eq!(force.norm(), 0.0);
    // Lowered by 1 mm more than the 1 cm gap, the flange presses with k · 1 mm.
    let Surface::Compliant(table) = demo.plant.contact else {
        panic!("the demo's table is compliant by default")
    };
    let pressed = table.force_on_environment(&(flange - 0.011 * SVector::<f64, 3>::z()));
    assert!((pressed.z + 1e4 * 0.001).abs() < 1e-9);
}

/// `simulate` touches the plane with the controller's controlled frame, whatever the plant's
/// own contact frame: a plant built at the end-effector gives the run of the demo at the flange.
#[test]
fn simulate_touches_the_plane_with_the_controlled_frame() {
    let q0 = start_posture_for::<Panda, 7>(None).expect("start posture");
    type Z = panda::Base;
    const M: usize = panda::BASE_PARAMETER_COUNT;
    let demo = Demo::<Z, 7, M, 3>::new_at_frame(short(), q0, panda::Frame::PandaLink8).expect("valid demo");
    let at_end_effector = Plant::<Z, 7, M>::with_payload_and_joint_terms(
        &demo.options.payload,
        &demo.options.true_joint_terms,
        demo.plant.contact,
    );
    assert_eq!(at_end_effector.contact_frame(), None);
    assert_eq!(*at_end_effector.parameters(), *demo.plant.parameters());
    let mut c = demo.controller(RunKind::Adaptive).expect("controller");
    let a = simulate(
        &at_end_effector,
        &mut c,
        &demo.scenario,
        &q0,
        &demo.options.sim,
        &mut |_| {},
    );
    let b = demo.run(RunKind::Adaptive, &mut |_| {}).expect("run");
    assert_eq!(a.status, RunStatus::Completed);
    assert_eq!(a.samples.len(), b.samples.len());
    for (x, y) in a.samples.iter().zip(&b.samples) {
        assert_eq!(x.true_force.to_bits(), y.true_force.to_bits(), "t = {}", x.t);
        assert_eq!(
            x.in_plane_error.to_bits(),
            y.in_plane_error.to_bits(),
            "t = {}",
            x.t
        );
    }
    assert!(b.samples.iter().any(|s| s.true_force > 5.0));
}

/// (3) An unknown frame name is an error that names the robot and lists its frames, the
/// end-effector first; a known one is found.
#[test]
fn an_unknown_frame_name_lists_the_robots_frames() {
    assert_eq!(
        frame_named::<Panda, 7>("panda_link8"),
        Ok(panda::Frame::PandaLink8)
    );
    assert_eq!(frame_named::<Ur5, 6>("tool0"), Ok(ur5::Frame::Tool0));
    let e = frame_named::<Panda, 7>("panda_link9").expect_err("no such frame");
    let ConfigError::Invalid {
        name: "frame",
        detail,
    } = &e
    else {
        panic!("{e:?}");
    };
    println!("{e}");
    assert!(
        detail
            .starts_with("panda has no frame 'panda_link9'; its frames: panda_hand_tcp (the end-effector), "),
        "{detail}"
    );
    for f in panda::Frame::ALL {
        assert!(detail.contains(f.name()), "{detail}");
    }
    assert!(e.to_string().contains("panda_rightfinger"));
    // Frame names are the description's, exactly.
    assert!(frame_named::<Ur5, 6>("Tool0").is_err());
}
