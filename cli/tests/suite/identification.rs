//! `dyngen excite` then `dyngen identify`, end to end: the trajectory is within the limits,
//! identification writes a description that loads, bad data is one error line naming file,
//! line and column.

use crate::common;

use common::{arg, dyngen, repository_file};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::JointTermValues;
use dyngen_identify::{read_csv, to_csv, with_joint_terms, with_payload};
use dyngen_runtime::SplitMix64;
use nalgebra::Vector3;

/// A standard normal sample (Box–Muller).
fn normal(rng: &mut SplitMix64) -> f64 {
    let u1 = rng.unit().max(f64::MIN_POSITIVE);
    let u2 = rng.unit();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

#[test]
fn excite_then_identify_then_load() {
    let dir = tempfile::tempdir().expect("temp dir");
    let description = dir.path().join("arm7_joint.yaml");
    let text = std::fs::read_to_string(repository_file("robots/arm7.yaml")).expect("arm7.yaml")
        + "joint_parameters:\n  columns: [armature, viscous, coulomb, offset]\n";
    std::fs::write(&description, text).expect("write");
    let nominal = load(&description).unwrap_or_else(|e| panic!("{e}")).model;

    let trajectory = dir.path().join("excitation.csv");
    let run = dyngen(&[
        "excite",
        arg(&description),
        "-o",
        arg(&trajectory),
        "--duration",
        "10",
        "--rate=100",
        "--iterations",
        "20",
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(run.stdout.contains("condition number"), "{}", run.output());
    // The written trajectory passes the reader's limit checks (positions and velocities).
    let excitation = read_csv(&trajectory, &nominal, false).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(excitation.len(), 1000);

    // Measure a "real" robot along it (a payload, joint friction and armature; exact
    // derivatives from the file, torques with noise of 1% of the rated torque).
    let values = vec![
        JointTermValues {
            armature: 0.2,
            viscous: 0.5,
            coulomb: 1.0,
            offset: 0.1,
        };
        7
    ];
    let payload = with_payload(&nominal, 1.5, Vector3::new(0.0, 0.0, 0.05), 0.04);
    let truth = with_joint_terms(&payload, &values, None);
    let noise: Vec<f64> = truth
        .joints()
        .iter()
        .map(|j| 0.01 * j.limits.map_or(1.0, |l| l.effort))
        .collect();
    let dynamics = NumericDynamics::new(&truth);
    let (qd, qdd) = (
        excitation.qd.as_ref().expect("qd"),
        excitation.qdd.as_ref().expect("qdd"),
    );
    let mut rng = SplitMix64::new(9);
    let mut data = excitation.clone();
    data.tau = Some(
        (0..excitation.len())
            .map(|k| {
                let tau = dynamics.inverse_dynamics(&excitation.q[k], &qd[k], &qdd[k]);
                tau.iter()
                    .zip(&noise)
                    .map(|(t, s)| t + s * normal(&mut rng))
                    .collect()
            })
            .collect(),
    );
    let data_path = dir.path().join("data.csv");
    std::fs::write(&data_path, to_csv(&nominal, &data)).expect("write data");

    let identified = dir.path().join("identified.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--output",
        arg(&identified),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stdout.contains("Ia[joint7]"),
        "prints the base parameters: {}",
        run.output()
    );
    assert!(
        run.stdout
            .contains("torque noise per joint (σ, from the weighted residuals; re-estimated")
            && run.stdout.contains("  joint7: σ = ")
            && run.stdout.contains("(compatible with the data)"),
        "prints the noise of every joint and the consistent estimate: {}",
        run.output()
    );
    assert!(!run.stderr.contains("warning"), "{}", run.output());
    let model = load(&identified).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(model.parameter_count(), 98);

    // As URDF (by the extension): the URDF and, for the armature, offsets and columns, its
    // wrapper beside it, which loads as the description the YAML run wrote.
    let urdf = dir.path().join("identified.urdf");
    let run = dyngen(&["identify", arg(&description), arg(&data_path), "-o", arg(&urdf)]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let wrapper = dir.path().join("identified.dyngen.yaml");
    assert!(
        run.stdout.contains(&format!("wrote {}", urdf.display()))
            && run.stdout.contains(&format!("wrote {}", wrapper.display()))
            && run.stdout.contains("  - armature (no URDF element): joint1 "),
        "{}",
        run.output()
    );
    let text = std::fs::read_to_string(&urdf).expect("the URDF");
    assert!(
        text.contains("<dynamics damping=") && text.contains("<inertial>"),
        "{text}"
    );
    let from_urdf = load(&wrapper).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(from_urdf.parameters(), model.parameters());

    // The table: θ_b, σ, %σ, the consistent estimate's θ_b and σ, a `*` on the parameters
    // whose σ is above 10% of their value, the name; then how many are marked.
    let rows = table(&run.stdout);
    assert_eq!(rows.len(), 69, "{}", run.output());
    let marked: Vec<&Row> = rows.iter().filter(|r| r.flagged).collect();
    for row in &rows {
        assert!(
            (row.percent - 100.0 * row.sigma / row.value.abs()).abs() <= 0.01 * row.percent.max(1.0),
            "{row:?}"
        );
        assert_eq!(row.flagged, row.percent > 10.0, "{row:?}");
    }
    assert!(
        !marked.is_empty() && marked.len() < rows.len(),
        "{}",
        run.output()
    );
    assert!(
        run.stdout.contains(&format!(
            "* {} of 69 base parameters have σ above 10% of their value",
            marked.len()
        )),
        "{}",
        run.output()
    );

    // Line by line (`--stream`): the same least squares (the table of base parameters and
    // their σ), and a description that loads.
    let stacked: Vec<(f64, f64)> = rows.iter().map(|r| (r.value, r.sigma)).collect();
    let streamed = dir.path().join("streamed.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--stream",
        "-o",
        arg(&streamed),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let lines: Vec<(f64, f64)> = table(&run.stdout).iter().map(|r| (r.value, r.sigma)).collect();
    assert_eq!(lines.len(), stacked.len(), "{}", run.output());
    assert_eq!(lines.len(), 69);
    for ((a, sa), (b, sb)) in stacked.iter().zip(&lines) {
        assert!(
            (a - b).abs() <= 1e-5 * a.abs() && (sa - sb).abs() <= 1e-5 * sa,
            "{a} ± {sa} vs {b} ± {sb}"
        );
    }
    load(&streamed).unwrap_or_else(|e| panic!("{e}"));

    // A limit no parameter meets: the identification is refused in one line and nothing is
    // written; with --force it is written, with a warning.
    let strict = dir.path().join("strict.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--max-relative-std",
        "1e-6",
        "-o",
        arg(&strict),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.starts_with(&format!(
            "error: {}: the identification cannot be trusted: every one of the 69 base parameters has a \
             relative standard deviation above 0.000001%",
            data_path.display()
        )) && run.stderr.contains("nothing written (--force writes it anyway)"),
        "{}",
        run.output()
    );
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
    assert!(!strict.exists());
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--max-relative-std",
        "1e-6",
        "--force",
        "-o",
        arg(&strict),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stderr.contains(&format!(
            "warning: {}: the identification cannot be trusted: every one of the 69",
            data_path.display()
        )) && run.stderr.contains("written anyway (--force)"),
        "{}",
        run.output()
    );
    load(&strict).unwrap_or_else(|e| panic!("{e}"));
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--max-relative-std",
        "0",
        "-o",
        arg(&strict),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr
            .contains("--max-relative-std 0: a limit is a positive percentage"),
        "{}",
        run.output()
    );

    // Without accelerations (the Lagrange equations over windows): a description that loads;
    // streamed, a clear refusal.
    let windowed = dir.path().join("windowed.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--observation",
        "momentum",
        "-o",
        arg(&windowed),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    load(&windowed).unwrap_or_else(|e| panic!("{e}"));
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&data_path),
        "--observation",
        "momentum",
        "--stream",
        "-o",
        arg(&windowed),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.contains("identified in the torque form"),
        "{}",
        run.output()
    );

    // Data no physically consistent robot explains (joint 7's torque with the wrong sign): a
    // warning, success, and a description that loads.
    let mut flipped = data.clone();
    for tau in flipped.tau.as_mut().expect("torques") {
        tau[6] = -tau[6];
    }
    let flipped_path = dir.path().join("flipped.csv");
    std::fs::write(&flipped_path, to_csv(&nominal, &flipped)).expect("write data");
    let warned = dir.path().join("warned.yaml");
    let run = dyngen(&[
        "identify",
        arg(&description),
        arg(&flipped_path),
        "-o",
        arg(&warned),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stderr.contains(&format!(
            "warning: {}: no physically consistent parameters fit the data",
            flipped_path.display()
        )) && run.stdout.contains("(NOT compatible with the data)"),
        "{}",
        run.output()
    );
    load(&warned).unwrap_or_else(|e| panic!("{e}"));

    // Bad data: one error line naming file, line and column, a failure, nothing written.
    let bad = dir.path().join("bad.csv");
    let text = std::fs::read_to_string(&data_path).expect("data");
    std::fs::write(&bad, text.replacen("q[joint3]", "q[joint33]", 1)).expect("write");
    let not_written = dir.path().join("not-written.yaml");
    let run = dyngen(&["identify", arg(&description), arg(&bad), "-o", arg(&not_written)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.starts_with(&format!(
            "error: {}:1: column 4 (q[joint33]): unknown joint 'joint33'",
            bad.display()
        )),
        "{}",
        run.output()
    );
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
    assert!(!not_written.exists());
}

/// A row of `dyngen identify`'s table of base parameters.
#[derive(Debug)]
struct Row {
    value: f64,
    sigma: f64,
    percent: f64,
    flagged: bool,
}

/// The rows of the table ([`common::table_rows`]).
fn table(stdout: &str) -> Vec<Row> {
    common::table_rows(stdout)
        .map(|l| {
            let fields: Vec<&str> = l.split_whitespace().collect();
            let number = |i: usize| -> f64 {
                fields[i]
                    .trim_end_matches('%')
                    .parse()
                    .unwrap_or_else(|_| panic!("field {i} of {l:?}"))
            };
            Row {
                value: number(0),
                sigma: number(1),
                percent: number(2),
                flagged: fields[5] == "*",
            }
        })
        .collect()
}
