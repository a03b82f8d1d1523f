//! `dyngen payload`, end to end: a payload identified from torques and a wrist sensor in a
//! data CSV, the description with it written and loaded; bad sensor columns and requests the
//! data cannot answer are one error line.

use crate::common;

use common::{arg, dyngen, repository_file};
use dyngen_codegen::description::load;
use dyngen_codegen::model::{Inertia, Model};
use dyngen_identify::{
    measure, measure_wrench, to_csv, with_body_at, FourierTrajectory, Samples, TrajectoryLimits,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};
use nalgebra::{Matrix3, Vector3};

fn total_mass(model: &Model) -> f64 {
    model.bodies().iter().map(|b| b.inertia.mass).sum()
}

/// arm7 with a 1.8 kg payload at the flange: positions and torques (noise 1% of rated
/// torque) and a wrist sensor at the flange, 10 s at 200 Hz.
fn payload_data(robot: &Model) -> Samples {
    let payload = Inertia {
        mass: 1.8,
        com: Vector3::new(0.01, 0.0, 0.07),
        inertia_com: Matrix3::from_diagonal(&Vector3::new(0.004, 0.005, 0.003)),
    };
    let truth = with_body_at(robot, "flange", &payload);
    let limits = TrajectoryLimits::from_model(robot, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut motion = FourierTrajectory::random(7, 5, 0.1, 3);
    motion.fit_into(&limits);
    let noise: Vec<f64> = robot
        .joints()
        .iter()
        .map(|j| 0.01 * j.limits.map_or(1.0, |l| l.effort))
        .collect();
    let mut data = measure(&truth, &motion, 10.0, 200.0, &noise, 1, false);
    let sensor_noise = [0.05, 0.05, 0.05, 0.003, 0.003, 0.003];
    data.wrench = Some(measure_wrench(
        robot,
        &truth,
        "flange",
        &motion,
        10.0,
        200.0,
        &sensor_noise,
        &[0.0; 6],
        2,
    ));
    data.sensor_frame = Some("flange".into());
    data
}

#[test]
fn payload_from_a_data_file_then_load() {
    let dir = tempfile::tempdir().expect("temp dir");
    let description = repository_file("robots/arm7.yaml");
    let robot = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    let data = payload_data(&robot);
    let data_path = dir.path().join("payload.csv");
    let text = to_csv(&robot, &data);
    assert!(text
        .lines()
        .next()
        .expect("header")
        .ends_with(",fx[flange],fy[flange],fz[flange],mx[flange],my[flange],mz[flange]"));
    std::fs::write(&data_path, &text).expect("write");

    let written = dir.path().join("with_payload.yaml");
    let run = dyngen(&["payload", arg(&description), arg(&data_path), "-o", arg(&written)]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stdout.contains("payload at frame 'flange' from Both"),
        "{}",
        run.output()
    );
    assert!(
        run.stdout.contains("sensor offset") && run.stdout.contains("  fz: σ = "),
        "{}",
        run.output()
    );
    let with_payload = load(&written).unwrap_or_else(|e| panic!("{e}")).model;
    let mass = total_mass(&with_payload) - total_mass(&robot);
    assert!((mass / 1.8 - 1.0).abs() <= 0.01, "payload mass {mass}");

    // A wrench column that names no frame, and one that names a frame the robot lacks.
    for (from, to, said) in [
        (
            "fx[flange]",
            "fx",
            "'fx' names no frame: a force/torque column is fx[<frame>]",
        ),
        (
            "mz[flange]",
            "mz[tool0]",
            "unknown frame 'tool0' (the robot's frames: flange",
        ),
    ] {
        let bad = dir.path().join("bad.csv");
        std::fs::write(&bad, text.replacen(from, to, 1)).expect("write");
        let run = dyngen(&["payload", arg(&description), arg(&bad), "-o", arg(&written)]);
        assert_eq!(run.code, Some(1), "{}", run.output());
        assert!(run.stderr.contains(said), "{}", run.output());
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
    }
    // Torques asked for, none in the file.
    let no_torques: String = {
        let mut d = data.clone();
        d.tau = None;
        to_csv(&robot, &d)
    };
    let bad = dir.path().join("no-torques.csv");
    std::fs::write(&bad, no_torques).expect("write");
    let run = dyngen(&[
        "payload",
        arg(&description),
        arg(&bad),
        "--from",
        "torques",
        "-o",
        arg(&written),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.contains("the data has no torque columns"),
        "{}",
        run.output()
    );
}

/// The sensor checked against itself and the torques: a sensor with the opposite sign and one
/// turned a quarter turn about its z axis are one error line that names the data file and the
/// likely cause, and nothing is written; `--force` writes the turned one with a warning. From
/// the sensor alone, the flipped one's negative mass comes with the hint.
#[test]
fn a_flipped_or_turned_sensor_is_one_line_naming_the_cause() {
    let dir = tempfile::tempdir().expect("temp dir");
    let description = repository_file("robots/arm7.yaml");
    let robot = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    let data = payload_data(&robot);
    let write = |name: &str, f: &dyn Fn([f64; 6]) -> [f64; 6]| {
        let mut changed = data.clone();
        for w in changed.wrench.as_mut().expect("a wrench") {
            *w = f(*w);
        }
        let path = dir.path().join(name);
        std::fs::write(&path, to_csv(&robot, &changed)).expect("write");
        path
    };
    let flipped = write("flipped.csv", &|w| w.map(|v| -v));
    let turned = write("turned.csv", &|w| [w[1], -w[0], w[2], w[4], -w[3], w[5]]);
    let written = dir.path().join("with_payload.yaml");

    let run = dyngen(&["payload", arg(&description), arg(&flipped), "-o", arg(&written)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.starts_with(&format!(
            "error: {}: the force/torque sensor and the joint torques disagree",
            flipped.display()
        )) && run.stderr.contains("likely cause: the sensor's sign"),
        "{}",
        run.output()
    );
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
    assert!(!written.exists());
    let run = dyngen(&[
        "payload",
        arg(&description),
        arg(&flipped),
        "--from",
        "wrench",
        "-o",
        arg(&written),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr
            .contains("the data shows no payload: its estimated mass is -1.8")
            && run.stderr.contains("negate its six columns"),
        "{}",
        run.output()
    );
    assert!(!written.exists());

    let run = dyngen(&["payload", arg(&description), arg(&turned), "-o", arg(&written)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.starts_with(&format!(
            "error: {}: the force/torque sensor's readings fit no payload",
            turned.display()
        )) && run.stderr.contains("likely cause: the sensor's frame")
            && run.stderr.contains("nothing written (--force writes it anyway)"),
        "{}",
        run.output()
    );
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
    assert!(!written.exists());
    let run = dyngen(&[
        "payload",
        arg(&description),
        arg(&turned),
        "--force",
        "-o",
        arg(&written),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stderr.contains(&format!(
            "warning: {}: the force/torque sensor's readings fit no payload",
            turned.display()
        )) && run.stderr.contains("written anyway (--force)"),
        "{}",
        run.output()
    );
    let text = std::fs::read_to_string(&written).expect("written");
    assert!(
        text.contains("# warning: the force/torque sensor's readings fit no payload"),
        "{text}"
    );
    load(&written).unwrap_or_else(|e| panic!("{e}"));
}
