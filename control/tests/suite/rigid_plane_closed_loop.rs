//! The controller on a rigid table (arm7, base parameters, adaptive law from half the
//! parameters, the demo's unknown payload): the tool never enters the table by more than
//! 1e-10 m, the measured force converges to the desired one, and the contact stays closed while
//! the controller presses and opens once it commands a lift (the desired force turning into a
//! desired height above the surface). A model stiffness that makes the force loop diverge on a
//! rigid table is refused before any run.

use dyngen_control::controller::{ConfigError, Desired, Measurement};
use dyngen_control::sim::{
    start_posture_for, Demo, DemoOptions, PlantState, RunKind, RunStatus, SurfaceKind,
};
use dyngen_generated::{arm7, Arm7};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{JointTrig, Kinematics};

type Z = arm7::Base;
const M: usize = arm7::BASE_PARAMETER_COUNT;

/// The model stiffness for the rigid table: the force loop's gain per period is 0.84 here.
const STIFFNESS: f64 = 1e5;

fn rigid_demo(circle_time: f64) -> Demo<Z, 7, M> {
    let q0 = start_posture_for::<Arm7, 7>(None).expect("start posture");
    let options = DemoOptions {
        stiffness: STIFFNESS,
        surface: SurfaceKind::Rigid,
        circle_time,
        ..DemoOptions::default()
    };
    Demo::new(options, q0).expect("valid demo")
}

fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0), |(s, n), v| (s + v * v, n + 1));
    (sum / f64::from(n.max(1))).sqrt()
}

#[test]
fn on_a_rigid_table_the_force_converges_and_the_tool_stays_on_it() {
    let demo = rigid_demo(1.0);
    let res = demo
        .run(RunKind::Adaptive, &mut |_| {})
        .expect("valid controller");
    assert_eq!(res.status, RunStatus::Completed);
    let deepest = res
        .samples
        .iter()
        .map(|s| s.penetration)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(deepest <= 1e-10, "{deepest:.3e} m inside the table");
    let touched = res
        .samples
        .iter()
        .find(|s| s.true_force > 0.0)
        .expect("touches")
        .t;
    let ramp_end = demo.scenario.approach_time + demo.scenario.ramp_time;
    let window = |from: f64, to: f64| {
        rms(res
            .samples
            .iter()
            .filter(|s| s.t >= from && s.t < to)
            .map(|s| s.true_force - s.desired_force))
    };
    let holding = window(ramp_end, demo.scenario.circle_start());
    let circling = window(demo.scenario.circle_start(), demo.scenario.duration() + 1.0);
    let last = res.samples.last().expect("samples");
    println!(
        "touched at {touched:.3} s; deepest {deepest:.3e} m; RMS force error holding {holding:.3e} N, \
         circling {circling:.3e} N; last {:.4} N",
        last.true_force
    );
    // The force, not a distance: on the table from the ramp on, and pressing to the end.
    assert!(touched < ramp_end && last.true_force > 0.0);
    assert!(holding <= 0.05 && circling <= 0.2, "{holding} {circling}");
    assert!((last.true_force - demo.options.target_force).abs() <= 0.2);
}

/// The desired motion of the lift: hold the pressed point in the plane and turn the force from
/// the target to `−k · 2 mm` (a desired height 2 mm above the model's surface) over 0.5 s
/// from `start`, by the demo's quintic blend written out.
fn lifting(demo: &Demo<Z, 7, M>, start: f64, t: f64) -> Desired<7, 1> {
    let mut d = demo.scenario.desired(start);
    let (from, to) = (demo.options.target_force, -STIFFNESS * 2e-3);
    let duration = 0.5;
    let u = ((t - start) / duration).clamp(0.0, 1.0);
    let inside = u > 0.0 && u < 1.0;
    let s = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
    let s1 = if inside {
        30.0 * u * u * (1.0 - u) * (1.0 - u) / duration
    } else {
        0.0
    };
    let s2 = if inside {
        60.0 * u * (1.0 - 3.0 * u + 2.0 * u * u) / (duration * duration)
    } else {
        0.0
    };
    d.force[0] = from + (to - from) * s;
    d.force_dot[0] = (to - from) * s1;
    d.force_ddot[0] = (to - from) * s2;
    // F_d = k (z_e − z_d).
    let k = demo.scenario.stiffness;
    d.position.z = demo.scenario.surface - d.force[0] / k;
    d.velocity.z = -d.force_dot[0] / k;
    d.acceleration.z = -d.force_ddot[0] / k;
    d
}

#[test]
fn the_contact_opens_when_the_controller_lifts_the_tool() {
    let demo = rigid_demo(0.0);
    let mut controller = demo.controller(RunKind::Adaptive).expect("controller");
    let plant = &demo.plant;
    let table = plant.contact.point().z;
    let dt = demo.options.sim.control_period;
    let lift_start = demo.scenario.circle_start();
    let end = lift_start + 1.0;
    let mut s = PlantState::at_rest(demo.q0);
    let mut tau = SVector::zeros();
    let (mut touched, mut opened, mut deepest) = (false, None, f64::NEG_INFINITY);
    let (mut crossed_zero, mut asked_at_opening) = (None, f64::NAN);
    for k in 0..=((end / dt).round() as usize) {
        let t = k as f64 * dt;
        let force = plant.contact_force(&s, &tau).expect("force");
        assert!(force.z <= 0.0, "the table never pulls: F̄ = {force}");
        let desired = if t < lift_start {
            demo.scenario.desired(t)
        } else {
            lifting(&demo, lift_start, t)
        };
        touched |= force.z < 0.0;
        if t < lift_start {
            // Once on the table, pressed until the lift.
            assert!(!touched || force.z < 0.0, "opened at {t} s, before the lift");
        } else {
            if crossed_zero.is_none() && desired.force[0] <= 0.0 {
                crossed_zero = Some(t);
            }
            if opened.is_none() && force.z == 0.0 {
                opened = Some(t);
                asked_at_opening = desired.force[0];
            }
        }
        let m = Measurement {
            q: s.q,
            qd: s.qd,
            force,
        };
        tau = controller.tick(&m, &desired, dt).expect("tick").tau;
        for _ in 0..demo.options.sim.substeps {
            s = plant
                .step(&s, &tau, dt / demo.options.sim.substeps as f64)
                .expect("step");
            let z = Arm7::forward_kinematics(&JointTrig::new(&s.q)).translation.z;
            deepest = deepest.max(table - z);
        }
    }
    let (crossed, opened) = (
        crossed_zero.expect("the lift is asked"),
        opened.expect("the contact opens"),
    );
    let height = Arm7::forward_kinematics(&JointTrig::new(&s.q)).translation.z - table;
    let asked = demo.scenario.surface + 2e-3 - table;
    println!(
        "lift from {lift_start:.3} s, force asked to 0 at {crossed:.3} s, contact open at {opened:.3} s \
         ({asked_at_opening:.2} N asked then); deepest {deepest:.3e} m; {:.3} mm above the table at the \
         end (asked {:.3} mm)",
        height * 1e3,
        asked * 1e3
    );
    // Opened by the lift: after it starts, and by the time the desired force is no force.
    assert!(
        touched && opened > lift_start && opened <= crossed + 0.02,
        "opened {opened}, asked {crossed}"
    );
    assert!(deepest <= 1e-10, "{deepest:.3e} m inside the table");
    assert!(
        (height - asked).abs() <= 1e-4,
        "{height} m above the table, {asked} asked"
    );
}

#[test]
fn a_model_stiffness_that_makes_the_force_loop_diverge_on_a_rigid_table_is_refused() {
    let q0 = start_posture_for::<Arm7, 7>(None).expect("start posture");
    let rigid = |stiffness: f64| {
        Demo::<Z, 7, M>::new(
            DemoOptions {
                stiffness,
                surface: SurfaceKind::Rigid,
                ..DemoOptions::default()
            },
            q0,
        )
    };
    // The demo's 10 kN/m: a gain of 8.4 per period.
    let Err(err @ ConfigError::RigidForceLoop { gain, unit, .. }) = rigid(1e4) else {
        panic!("a diverging force loop must be refused")
    };
    println!("{err}");
    assert!((gain - 8.38).abs() < 0.05, "gain {gain}");
    assert!(err
        .to_string()
        .contains("raise the model stiffness k from 1e4 to at least"));
    // The stiffness it names for a gain of 1 is accepted, and so is the compliant table.
    rigid(unit).expect("a gain of 1");
    Demo::<Z, 7, M>::new(DemoOptions::default(), q0).expect("a compliant table");
}
