//! A data file identified line by line gives the estimate of the stacked path, whether the
//! file has velocities and accelerations or they are computed window by window, and reports
//! a bad line as the stacked path does.

use crate::common;

use common::{arm7_noise, arm7_nominal, arm7_truth};
use dyngen_identify::{
    identify, identify_file, measure, read_csv, to_csv, BaseModel, FourierTrajectory, Identification,
    IdentifyOptions, Progress, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY,
};
use std::path::{Path, PathBuf};

fn data_file(name: &str, with_derivatives: bool) -> (tempfile::TempDir, PathBuf) {
    let nominal = arm7_nominal();
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, 5);
    t.fit_into(&limits);
    let samples = measure(
        &arm7_truth(),
        &t,
        12.0,
        250.0,
        &arm7_noise(&nominal),
        3,
        with_derivatives,
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(name);
    std::fs::write(&path, to_csv(&nominal, &samples)).expect("write");
    (dir, path)
}

/// Both paths on one file; the streamed one with windows much shorter than the log.
fn both(path: &Path) -> (Identification, Identification, Vec<Progress>) {
    let model = arm7_nominal();
    let options = IdentifyOptions {
        stream_window: 700,
        ..IdentifyOptions::default()
    };
    let stacked = identify(&model, &read_csv(path, &model, true).expect("read"), &options).expect("stacked");
    let mut progress = Vec::new();
    let streamed = identify_file(&model, &BaseModel::new(&model), path, &options, |p| {
        progress.push(*p)
    })
    .expect("streamed");
    (stacked, streamed, progress)
}

fn assert_same_estimate(stacked: &Identification, streamed: &Identification) {
    assert_eq!(stacked.samples_used, streamed.samples_used);
    assert_eq!(stacked.differentiated, streamed.differentiated);
    let (a, b) = (&stacked.base, &streamed.base);
    let mut worst = 0.0f64;
    for k in 0..a.theta_b.len() {
        // Relative to the parameter, or to its uncertainty for one near zero.
        let size = a.theta_b[k].abs().max(a.std_dev[k]);
        let difference = (a.theta_b[k] - b.theta_b[k]).abs() / size;
        worst = worst.max(difference);
        assert!(
            difference <= 1e-9,
            "{}: stacked {} streamed {}",
            a.names[k],
            a.theta_b[k],
            b.theta_b[k]
        );
        assert!(
            (a.std_dev[k] / b.std_dev[k] - 1.0).abs() <= 1e-9,
            "σ of {}",
            a.names[k]
        );
    }
    for (x, y) in a.joint_noise.iter().zip(&b.joint_noise) {
        assert!((x / y - 1.0).abs() <= 1e-9, "joint noise {x} vs {y}");
    }
    println!("largest relative difference of θ_b: {worst:.2e}");
}

#[test]
fn a_file_with_derivatives_streams_to_the_stacked_estimate() {
    let (_dir, path) = data_file("given.csv", true);
    let (stacked, streamed, progress) = both(&path);
    assert!(!streamed.differentiated);
    assert_same_estimate(&stacked, &streamed);
    assert_eq!(progress.last().map(|p| p.samples), Some(streamed.samples_used));
}

#[test]
fn derivatives_computed_window_by_window_equal_the_whole_signal_s() {
    let (_dir, path) = data_file("positions.csv", false);
    let (stacked, streamed, progress) = both(&path);
    assert!(streamed.differentiated);
    // Several windows and both passes were made.
    assert!(streamed.samples_used > 3 * 700);
    assert!(progress.iter().any(|p| p.pass == 1) && progress.iter().any(|p| p.pass == 2));
    assert_same_estimate(&stacked, &streamed);
}

#[test]
fn a_bad_line_is_the_error_the_stacked_path_gives() {
    let (dir, path) = data_file("bad.csv", false);
    let text = std::fs::read_to_string(&path).expect("read");
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    // Line 1500: a torque that is not a number; then a second file with time going back.
    let mut fields: Vec<String> = lines[1499].split(',').map(str::to_owned).collect();
    let last = fields.len() - 1;
    fields[last] = "12..5".into();
    lines[1499] = fields.join(",");
    let bad = dir.path().join("not-a-number.csv");
    std::fs::write(&bad, lines.join("\n")).expect("write");
    let model = arm7_nominal();
    let options = IdentifyOptions::default();
    let stacked = read_csv(&bad, &model, true).expect_err("refused").to_string();
    let streamed = identify_file(&model, &BaseModel::new(&model), &bad, &options, |_| {})
        .expect_err("refused")
        .to_string();
    assert_eq!(stacked, streamed);
    assert!(
        stacked.contains(":1500: column 15 (tau[joint7]): '12..5' is not a number"),
        "{stacked}"
    );
    // Uneven sampling is found on the line it happens, by both.
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let mut fields: Vec<String> = lines[2000].split(',').map(str::to_owned).collect();
    let t: f64 = fields[0].parse().expect("time");
    fields[0] = format!("{}", t + 0.002);
    lines[2000] = fields.join(",");
    let uneven = dir.path().join("uneven.csv");
    std::fs::write(&uneven, lines.join("\n")).expect("write");
    let samples = read_csv(&uneven, &model, true).expect("reads");
    let stacked = identify(&model, &samples, &options)
        .expect_err("refused")
        .to_string();
    let streamed = identify_file(&model, &BaseModel::new(&model), &uneven, &options, |_| {})
        .expect_err("refused")
        .to_string();
    assert!(
        streamed.contains(&format!("{}:2001: column 1 (time): time step", uneven.display())),
        "{streamed}"
    );
    assert!(
        stacked.contains(&format!("{}:2001: column 1 (time): time step", uneven.display())),
        "{stacked}"
    );
}

/// A named pipe in place of the file, fed by another thread: read once, in one pass (the step
/// from the first window, 700 samples), it gives the estimate of the file read twice.
#[cfg(unix)]
#[test]
fn a_pipe_is_read_in_one_pass_to_the_same_estimate() {
    let (dir, path) = data_file("positions.csv", false);
    let (stacked, _, _) = both(&path);
    let pipe = dir.path().join("pipe.csv");
    let made = std::process::Command::new("mkfifo")
        .arg(&pipe)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let writer = {
        let (from, to) = (path.clone(), pipe.clone());
        std::thread::spawn(move || {
            let text = std::fs::read(&from).expect("read");
            std::fs::write(&to, text).expect("write into the pipe");
        })
    };
    let model = arm7_nominal();
    let options = IdentifyOptions {
        stream_window: 700,
        ..IdentifyOptions::default()
    };
    let mut progress = Vec::new();
    let streamed = identify_file(&model, &BaseModel::new(&model), &pipe, &options, |p| {
        progress.push(*p)
    })
    .expect("streamed from the pipe");
    writer.join().expect("the writer finishes");
    assert!(streamed.differentiated);
    assert!(progress.iter().all(|p| p.pass == 2), "one pass");
    assert_same_estimate(&stacked, &streamed);
}
