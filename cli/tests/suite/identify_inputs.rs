//! `dyngen identify`'s inputs and messages: data from a pipe, streamed or not, gives the file's
//! estimate; a dropped or malformed sample is an error naming the data file; the loader's
//! warnings about the description written name the file `-o` names and the line it has there.

use crate::common;

use common::{arg, assert_same_table, dyngen, dyngen_with_stdin, repository_file, table};
use dyngen_codegen::description::load;
use dyngen_identify::{
    measure, to_csv, FourierTrajectory, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY,
};
use std::path::{Path, PathBuf};

/// arm7 (rigid) measured along a random motion: positions only (velocities and accelerations
/// are computed), torques with noise of 1% of the rated torque; 8 s at 200 Hz.
fn positions_data(dir: &Path) -> (PathBuf, PathBuf, String) {
    positions_data_with_noise(dir, 0.01)
}

/// [`positions_data`] with torque noise of `fraction` of the rated torque.
fn positions_data_with_noise(dir: &Path, fraction: f64) -> (PathBuf, PathBuf, String) {
    let description = repository_file("robots/arm7.yaml");
    let robot = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    let limits = TrajectoryLimits::from_model(&robot, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut motion = FourierTrajectory::random(7, 5, 0.1, 4);
    motion.fit_into(&limits);
    let noise: Vec<f64> = robot
        .joints()
        .iter()
        .map(|j| fraction * j.limits.map_or(1.0, |l| l.effort))
        .collect();
    let samples = measure(&robot, &motion, 8.0, 200.0, &noise, 6, false);
    let text = to_csv(&robot, &samples);
    let data = dir.join("positions.csv");
    std::fs::write(&data, &text).expect("write");
    (description, data, text)
}

/// What stderr says besides the note that the rigid arm7 identifies no joint terms.
fn errors(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| !(l.starts_with("note: ") && l.ends_with("friction and armature are not identified")))
        .collect()
}

/// The data through a pipe, as `-` and as `/dev/stdin`, streamed (one pass: a second would
/// find the pipe used up) and not: the table of the file read twice.
#[test]
fn data_from_a_pipe_gives_the_file_s_estimate() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (description, data, text) = positions_data(dir.path());
    let out = dir.path().join("identified.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data),
        "--stream",
        "-o",
        arg(&out),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let from_file = table(&run.stdout);
    for input in ["-", "/dev/stdin"] {
        for stream in [true, false] {
            let mut args = vec!["identify", arg(&description), input, "-o", arg(&out)];
            if stream {
                args.push("--stream");
            }
            let run = dyngen_with_stdin(&args, text.as_bytes());
            let what = format!("{input}, stream {stream}: {}", run.output());
            assert_eq!(run.code, Some(0), "{what}");
            assert_same_table(&from_file, &table(&run.stdout), &what);
            assert!(!run.stderr.contains("warning"), "{what}");
            let written = std::fs::read_to_string(&out).expect("written");
            let source = if input == "-" { "<stdin>" } else { input };
            assert!(
                written.contains(&format!("Identified by `dyngen identify` from {source}:")),
                "{written}"
            );
        }
    }
    // A bad line from a pipe names it as the standard input.
    let bad = text.replacen("\n0.5,", "\n0.5x,", 1);
    assert_ne!(bad, text);
    let run = dyngen_with_stdin(
        &["identify", arg(&description), "-", "--stream", "-o", arg(&out)],
        bad.as_bytes(),
    );
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        errors(&run.stderr) == ["error: <stdin>:102: column 1 (time): '0.5x' is not a number"],
        "{}",
        run.output()
    );
}

/// Without `--stream`, a dropped sample (uneven time steps, which the filter cannot take)
/// and a malformed one are one error line that names the data file, the line and the column.
#[test]
fn a_dropped_or_malformed_sample_names_the_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (description, _, text) = positions_data(dir.path());
    let out = dir.path().join("identified.yaml");
    let lines: Vec<&str> = text.lines().collect();
    // File line 501 dropped: the sample now on line 501 is two steps after the one before.
    let dropped: Vec<&str> = lines
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != 500)
        .map(|(_, l)| *l)
        .collect();
    let path = dir.path().join("dropped.csv");
    std::fs::write(&path, dropped.join("\n")).expect("write");
    let run = dyngen(&["identify", arg(&description), arg(&path), "-o", arg(&out)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    let said = errors(&run.stderr);
    assert!(
        said.len() == 1
            && said[0].starts_with(&format!(
                "error: {}:501: column 1 (time): time step 0.0099",
                path.display()
            ))
            && said[0].contains("differs from the mean step 0.0050"),
        "{}",
        run.output()
    );
    assert!(!out.exists());

    let mut malformed: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    malformed[300] = malformed[300].replacen(',', ",,", 1);
    let path = dir.path().join("malformed.csv");
    std::fs::write(&path, malformed.join("\n")).expect("write");
    let run = dyngen(&["identify", arg(&description), arg(&path), "-o", arg(&out)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    let said = errors(&run.stderr);
    assert!(
        said.len() == 1 && said[0].starts_with(&format!("error: {}:301: ", path.display())),
        "{}",
        run.output()
    );
    assert!(!out.exists());
}

/// A description the loader warns about (joint 7 with an effort limit of 0): the description
/// written keeps it, and the warning about the written file names the file `-o` names and the
/// line the limit is on in it; the warning is not copied into the file, whose loading says it.
#[test]
fn warnings_about_the_written_file_name_it_and_its_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, data, _) = positions_data(dir.path());
    let text = std::fs::read_to_string(repository_file("robots/arm7.yaml")).expect("arm7.yaml");
    let limit = "velocity: 2.356194490192345, effort: 40.0 }";
    assert_eq!(text.matches(limit).count(), 2, "joints 6 and 7 have this limit");
    let at = text.rfind(limit).expect("joint 7's limit");
    let zero = format!(
        "{}{}",
        &text[..at],
        text[at..].replacen("effort: 40.0", "effort: 0.0", 1)
    );
    let description = dir.path().join("arm7_no_effort.yaml");
    std::fs::write(&description, zero).expect("write");

    let out = dir.path().join("my_arm.yaml");
    let run = dyngen(&["identify", arg(&description), arg(&data), "-o", arg(&out)]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let written = std::fs::read_to_string(&out).expect("written");
    let line = 1 + written
        .lines()
        .position(|l| l.contains("effort: 0,") || l.contains("effort: 0 }"))
        .expect("the limit is written");
    let prefix = format!("warning: {}:{line}:", out.display());
    let warnings: Vec<&str> = run.stderr.lines().filter(|l| l.starts_with(&prefix)).collect();
    assert_eq!(warnings.len(), 1, "{}\n{written}", run.output());
    assert!(
        warnings[0].contains("joint 'joint7'") && warnings[0].contains("effort limit is 0"),
        "{}",
        run.output()
    );
    // The description's own warning names the description.
    assert!(
        run.stderr
            .contains(&format!("warning: {}:", description.display())),
        "{}",
        run.output()
    );
    assert!(!written.contains("effort limit is 0"), "{written}");
    assert!(!run.stderr.contains("identified.yaml"), "{}", run.output());
}

/// `text` (a data file) as a logger whose torques lag by `lag` samples writes it: each line
/// keeps its time and motion and takes the torques of the line `lag` before (the first `lag`
/// lines dropped).
fn delayed(text: &str, lag: usize) -> String {
    let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let first_tau = lines[0]
        .iter()
        .position(|c| c.starts_with("tau["))
        .expect("torques");
    std::iter::once(lines[0].join(","))
        .chain((1 + lag..lines.len()).map(|i| {
            let mut fields = lines[i][..first_tau].to_vec();
            fields.extend_from_slice(&lines[i - lag][first_tau..]);
            fields.join(",")
        }))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A log whose torques are 3 samples late: `--estimate-delay 10` finds the delay and says it
/// in samples and seconds; at ten times the noise, where one sample's change of the torques is
/// lost in it, a warning says the delay is barely determined; with `--stream` it is refused
/// in one line. (One sample, 5 ms, of this slow motion changes the torques by less than 1% of
/// the rated torque.)
#[test]
fn a_torque_delay_is_found() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (description, _, quiet) = positions_data_with_noise(dir.path(), 0.001);
    let path = dir.path().join("delayed.csv");
    std::fs::write(&path, delayed(&quiet, 3)).expect("write");
    let out = dir.path().join("identified.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&path),
        "--estimate-delay",
        "10",
        "-o",
        arg(&out),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stdout
            .contains("torque delay: 3 samples (0.0150 s) behind the positions (searched over ±10;"),
        "{}",
        run.output()
    );
    assert!(!run.stderr.contains("barely determined"), "{}", run.output());
    let written = std::fs::read_to_string(&out).expect("written");
    assert!(
        written.contains("Each torque was paired with the motion 3 samples earlier"),
        "{written}"
    );

    let (_, _, noisy) = positions_data(dir.path());
    let noisy_path = dir.path().join("noisy_delayed.csv");
    std::fs::write(&noisy_path, delayed(&noisy, 3)).expect("write");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&noisy_path),
        "--estimate-delay",
        "10",
        "-o",
        arg(&out),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stderr.contains(&format!(
            "warning: {}: the torque delay is barely determined",
            noisy_path.display()
        )),
        "{}",
        run.output()
    );

    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&path),
        "--estimate-delay",
        "10",
        "--stream",
        "-o",
        arg(&out),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert_eq!(
        errors(&run.stderr),
        ["error: a delay is searched on the whole log: identify it without streaming"],
        "{}",
        run.output()
    );
}

/// Data that cannot determine some parameter (joint 1 never moves: nothing in the data
/// multiplies the inertia about its axis) is one error line naming the parameter, and
/// nothing is written, `--force` or not: there is no estimate to write.
#[test]
fn a_rank_deficient_excitation_writes_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (description, _, text) = positions_data(dir.path());
    let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let column = lines[0]
        .iter()
        .position(|c| *c == "q[joint1]")
        .expect("q[joint1]");
    let still: Vec<String> = lines
        .iter()
        .enumerate()
        .map(|(i, fields)| {
            let mut fields: Vec<&str> = fields.clone();
            if i > 0 {
                fields[column] = "0.3";
            }
            fields.join(",")
        })
        .collect();
    let path = dir.path().join("still.csv");
    std::fs::write(&path, still.join("\n")).expect("write");
    let out = dir.path().join("identified.yaml");
    for force in [false, true] {
        let mut args = vec!["identify", arg(&description), arg(&path), "-o", arg(&out)];
        if force {
            args.push("--force");
        }
        let run = dyngen(&args);
        assert_eq!(run.code, Some(1), "{}", run.output());
        let said = errors(&run.stderr);
        assert!(
            said.len() == 1
                && said[0].starts_with("error: base parameter '")
                && said[0].contains("cannot be determined"),
            "{}",
            run.output()
        );
        assert!(!out.exists());
    }
}
