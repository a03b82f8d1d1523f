//! Bad data, as a person sees it: one clear error naming the file, line and column or the
//! joint, never a silent wrong estimate. The messages are listed in TESTING.md.

use crate::common;

use common::{arm7_nominal, arm7_truth};
use dyngen_identify::measure;
use dyngen_identify::{identify, IdentifyOptions};
use dyngen_identify::{read_csv, to_csv, Samples};
use dyngen_identify::{FourierTrajectory, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY};

fn good_samples() -> Samples {
    let nominal = arm7_nominal();
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, 11);
    t.fit_into(&limits);
    measure(&arm7_truth(), &t, 1.0, 10.0, &[0.0; 7], 1, false)
}

/// Writes `text` to a file named `name` in a fresh directory and reads it for arm7.
fn read_error(name: &str, text: &str) -> String {
    let scratch = tempfile::Builder::new()
        .prefix("dyngen-bad-data-")
        .tempdir()
        .expect("scratch dir");
    let dir = scratch.path();
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    let result = read_csv(&path, &arm7_nominal(), true);
    match result {
        Ok(_) => panic!("{name} was accepted"),
        Err(e) => e.to_string().replace(&format!("{}/", dir.display()), ""),
    }
}

fn replace_line(text: &str, line: usize, f: impl Fn(&str) -> String) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == line { f(l) } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `text` with columns `names` added, every sample 0 in them.
fn with_columns(text: &str, names: &[&str]) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let added: Vec<String> = names
                .iter()
                .map(|n| if i == 0 { n.to_string() } else { "0".into() })
                .collect();
            format!("{l},{}", added.join(","))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Replaces field `column` (1-based) of line `line`.
fn replace_field(text: &str, line: usize, column: usize, value: &str) -> String {
    replace_line(text, line, |l| {
        let mut fields: Vec<&str> = l.split(',').collect();
        fields[column - 1] = value;
        fields.join(",")
    })
}

#[test]
fn every_bad_data_file_is_one_clear_error() {
    let good = to_csv(&arm7_nominal(), &good_samples());
    let cases = [
        ("missing-column.csv", good.replace(",tau[joint3]", ",torque3")),
        ("missing-torque.csv", {
            // Drop the tau[joint7] column everywhere.
            let c = good
                .lines()
                .next()
                .unwrap()
                .split(',')
                .position(|f| f == "tau[joint7]")
                .unwrap();
            good.lines()
                .map(|l| {
                    l.split(',')
                        .enumerate()
                        .filter(|(i, _)| *i != c)
                        .map(|(_, f)| f)
                        .collect::<Vec<_>>()
                        .join(",")
                })
                .collect::<Vec<_>>()
                .join("\n")
        }),
        ("unknown-joint.csv", good.replace("q[joint2]", "q[joint9]")),
        ("duplicate-column.csv", good.replace("q[joint2]", "q[joint1]")),
        ("nan.csv", replace_field(&good, 4, 3, "NaN")),
        ("not-a-number.csv", replace_field(&good, 5, 9, "1.2.3")),
        (
            "short-line.csv",
            replace_line(&good, 6, |l| l.rsplit_once(',').unwrap().0.to_string()),
        ),
        ("time-goes-back.csv", replace_field(&good, 7, 1, "0.1")),
        ("outside-limits.csv", replace_field(&good, 8, 3, "2.5")),
        ("header-only.csv", good.lines().next().unwrap().to_string()),
        ("sensor-without-frame.csv", with_columns(&good, &["fx"])),
        (
            "sensor-unknown-frame.csv",
            with_columns(
                &good,
                &[
                    "fx[tool]", "fy[tool]", "fz[tool]", "mx[tool]", "my[tool]", "mz[tool]",
                ],
            ),
        ),
        (
            "sensor-incomplete.csv",
            with_columns(
                &good,
                &[
                    "fx[flange]",
                    "fy[flange]",
                    "fz[flange]",
                    "mx[flange]",
                    "my[flange]",
                ],
            ),
        ),
    ];
    let mut report = String::new();
    for (name, text) in &cases {
        report += &format!("{}\n", read_error(name, text));
    }
    print!("{report}");
    let expected = "\
missing-column.csv:1: column 11 (torque3): unknown column: expected time, q[<joint>], qd[<joint>], qdd[<joint>], tau[<joint>] or a force/torque sensor's fx, fy, fz, mx, my, mz[<frame>]
missing-torque.csv:1: missing column 'tau[joint7]' for joint 'joint7' (every joint needs its torque)
unknown-joint.csv:1: column 3 (q[joint9]): unknown joint 'joint9' (the robot's moving joints: joint1, joint2, joint3, joint4, joint5, joint6, joint7)
duplicate-column.csv:1: column 3 (q[joint1]): duplicate column (first at column 2)
nan.csv:4: column 3 (q[joint2]): NaN is not a finite number
not-a-number.csv:5: column 9 (tau[joint1]): '1.2.3' is not a number
short-line.csv:6: 14 fields, but the header has 15 columns
time-goes-back.csv:7: column 1 (time): time 0.1 does not increase (the sample before, line 6, is at 0.4)
outside-limits.csv:8: column 3 (q[joint2]): joint 'joint2': position 2.5 is outside the joint limits [-2.0943951023931953, 2.0943951023931953]
header-only.csv: no samples: the file has a header line only
sensor-without-frame.csv:1: column 16 (fx): 'fx' names no frame: a force/torque column is fx[<frame>], with the frame of the description the sensor measures in (the robot's frames: flange)
sensor-unknown-frame.csv:1: column 16 (fx[tool]): unknown frame 'tool' (the robot's frames: flange; name others with `frames:` in the description)
sensor-incomplete.csv:1: missing column 'mz[flange]': a force/torque sensor needs all six of fx, fy, fz, mx, my, mz
";
    assert_eq!(report, expected);
    let testing =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../TESTING.md")).expect("TESTING.md");
    assert!(
        testing.contains(expected),
        "TESTING.md lists these messages as they are"
    );
}

/// What spreadsheets and loggers write around the same numbers (a byte-order mark, CRLF line
/// ends, quoted fields, blank lines) reads as the plain file; an empty field is an error at
/// its place.
#[test]
fn files_as_tools_write_them_read_as_the_plain_file() {
    let good = to_csv(&arm7_nominal(), &good_samples());
    let read = |name: &str, text: &str| {
        let scratch = tempfile::Builder::new()
            .prefix("dyngen-file-forms-")
            .tempdir()
            .expect("scratch dir");
        let path = scratch.path().join(name);
        std::fs::write(&path, text).expect("write");
        let samples = read_csv(&path, &arm7_nominal(), true).unwrap_or_else(|e| panic!("{name}: {e}"));
        samples
    };
    let plain = read("plain.csv", &good);
    let quoted: String = good
        .lines()
        .map(|l| {
            l.split(',')
                .map(|f| format!("\"{f}\""))
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect::<Vec<_>>()
        .join("\n");
    for (name, text) in [
        ("bom.csv", format!("\u{feff}{good}")),
        ("crlf.csv", good.replace('\n', "\r\n")),
        ("quoted.csv", quoted),
        ("blank-lines.csv", good.replacen('\n', "\n\n", 3) + "\n\n"),
    ] {
        let other = read(name, &text);
        assert_eq!(
            (&other.time, &other.q, &other.tau),
            (&plain.time, &plain.q, &plain.tau),
            "{name}"
        );
    }
    let empty = read_error("empty-field.csv", &replace_field(&good, 4, 5, ""));
    assert_eq!(
        empty,
        "empty-field.csv:4: column 5 (q[joint4]): empty field: expected a number"
    );
}

/// Data in which a joint never moves cannot determine its parameters: the error names one
/// and says why, instead of returning a number.
#[test]
fn data_that_cannot_determine_a_parameter_says_which_and_why() {
    let nominal = arm7_nominal();
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, 11);
    t.fit_into(&limits);
    // Joint 7 held still.
    t.a[6].iter_mut().chain(t.b[6].iter_mut()).for_each(|c| *c = 0.0);
    let samples = measure(&arm7_truth(), &t, 10.0, 50.0, &[0.0; 7], 1, true);
    let err = identify(&nominal, &samples, &IdentifyOptions::default()).expect_err("unidentifiable");
    let msg = err.to_string();
    println!("{msg}");
    assert!(msg.starts_with("base parameter '"), "{msg}");
    assert!(msg.contains("cannot be determined"), "{msg}");
    assert!(
        msg.contains("joint7]") || msg.contains("link7]"),
        "names a parameter of the still joint: {msg}"
    );
}

#[test]
fn too_few_samples_is_an_error() {
    let mut samples = good_samples();
    samples.qd = Some(samples.q.clone());
    samples.qdd = Some(samples.q.clone());
    samples.time.truncate(5);
    samples.q.truncate(5);
    for v in [samples.qd.as_mut(), samples.qdd.as_mut(), samples.tau.as_mut()]
        .into_iter()
        .flatten()
    {
        v.truncate(5);
    }
    let err = identify(&arm7_nominal(), &samples, &IdentifyOptions::default()).expect_err("too few");
    assert!(
        err.to_string().starts_with("5 samples give 35 equations for"),
        "{err}"
    );
}

/// An error from below keeps it as its source: the I/O error of a file that is not there, the
/// CSV reader's of a line that is not UTF-8 (with the line it is on).
#[test]
fn errors_from_below_keep_their_source() {
    use dyngen_identify::IdentifyError;
    use std::error::Error as _;
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("missing.csv");
    let err = read_csv(&missing, &arm7_nominal(), true).expect_err("no file");
    let IdentifyError::Read { path, source } = &err else {
        panic!("not a read error: {err:?}")
    };
    assert_eq!(path, &missing);
    assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
    assert!(err.source().is_some());
    assert!(err
        .to_string()
        .starts_with(&format!("{}: cannot read the data file: ", missing.display())));

    let good = to_csv(&arm7_nominal(), &good_samples());
    let mut bytes = good.into_bytes();
    let third_line = bytes
        .iter()
        .enumerate()
        .filter(|(_, &b)| b == b'\n')
        .nth(1)
        .map(|(i, _)| i + 1)
        .expect("three lines");
    bytes[third_line] = 0xff;
    let not_utf8 = dir.path().join("not-utf8.csv");
    std::fs::write(&not_utf8, bytes).expect("write");
    let err = read_csv(&not_utf8, &arm7_nominal(), true).expect_err("not UTF-8");
    assert!(matches!(err, IdentifyError::Csv { .. }), "{err:?}");
    assert!(err.source().is_some());
    assert!(
        err.to_string()
            .starts_with(&format!("{}:3: not valid CSV", not_utf8.display())),
        "{err}"
    );
}

/// Defective closed-loop data given to IDIM-IV and DIDIM (and the least squares they start
/// from): each is one line naming the sample, joint or setting, never a panic or an estimate.
#[test]
fn defective_closed_loop_data_is_one_clear_error() {
    use crate::common::closed_loop::ur5_with_tool;
    use dyngen_identify::{identify_base, ControlLaw, Estimator};

    let case = ur5_with_tool();
    let (samples, reference) = case.measure(case.logging(1));
    let error = |samples: &Samples, options: IdentifyOptions| {
        let e = identify_base(&case.description, samples, &options)
            .expect_err("refused")
            .to_string();
        assert!(!e.contains('\n'), "{e}");
        e
    };
    let with_loop = |estimator: Estimator| IdentifyOptions {
        estimator,
        closed_loop: Some(case.closed_loop(&reference)),
        ..IdentifyOptions::default()
    };
    for estimator in [
        Estimator::LeastSquares,
        Estimator::InstrumentalVariables,
        Estimator::Didim,
    ] {
        let options = || match estimator {
            Estimator::LeastSquares => IdentifyOptions::default(),
            _ => with_loop(estimator),
        };
        let mut nan = samples.clone();
        nan.q[500][2] = f64::NAN;
        assert_eq!(
            error(&nan, options()),
            "sample 500 (t = 2.5 s): q[elbow_joint]: NaN is not a finite number"
        );
        let mut nan = samples.clone();
        nan.tau.as_mut().expect("torques")[700][1] = f64::INFINITY;
        assert_eq!(
            error(&nan, options()),
            "sample 700 (t = 3.5 s): tau[shoulder_lift_joint]: inf is not a finite number"
        );
        let mut short = samples.clone();
        short.time.truncate(60);
        short.q.truncate(60);
        short.tau.as_mut().expect("torques").truncate(60);
        assert_eq!(
            error(&short, options()),
            "60 samples: the filter's transients take 30 at each end; give more samples or q̇ and q̈"
        );
        // A joint whose encoder reads one value all along (a brake, a dead encoder).
        let mut still = samples.clone();
        let held = still.q[0][3];
        still.q.iter_mut().for_each(|q| q[3] = held);
        let e = error(&still, options());
        println!("{estimator}, a joint that never moves: {e}");
        assert!(e.starts_with("base parameter '"), "{e}");
        assert!(
            e.contains("wrist_1_joint]") && e.contains("cannot be determined"),
            "{e}"
        );
    }
    for estimator in [Estimator::InstrumentalVariables, Estimator::Didim] {
        let mut half = reference.clone();
        half.time.truncate(1000);
        half.q.truncate(1000);
        half.qd.truncate(1000);
        let mut options = with_loop(estimator);
        options.closed_loop.as_mut().expect("a loop").reference = half;
        let e = error(&samples, options);
        assert!(
            e.starts_with("the reference covers 0 s to 4.995 s, the data 0 s to 9.")
                && e.ends_with("the reference must cover the whole log"),
            "{e}"
        );
        let mut options = with_loop(estimator);
        let law: &mut ControlLaw = &mut options.closed_loop.as_mut().expect("a loop").law;
        law.gains.truncate(5);
        assert_eq!(
            error(&samples, options),
            "the control law has no gains for joint wrist_3_joint (every joint needs kp and kd)"
        );
    }
    let without_loop = IdentifyOptions {
        estimator: Estimator::Didim,
        ..IdentifyOptions::default()
    };
    assert!(error(&samples, without_loop).starts_with("DIDIM simulates the loop the torques come from"));
}
