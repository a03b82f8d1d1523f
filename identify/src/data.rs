//! The data CSV: one header line of column names, then one sample per line.
//!
//! Columns (any order): `time` (s, strictly increasing); per joint, by the description's joint
//! name, `q[<joint>]` (rad or m) and `tau[<joint>]` (N·m or N), required; `qd[<joint>]` and
//! `qdd[<joint>]`, optional but all-or-none per kind (when missing, identification computes
//! them with a zero-phase filter). Fields are numbers separated by commas (read with the `csv`
//! crate, so a quoted field may hold a comma), surrounding spaces ignored; blank lines are
//! skipped. Every problem is an error naming the
//! file, line and column (or the joint): unknown or missing columns, a field that is not a
//! finite number, time that does not increase, a position or velocity outside the joint
//! limits. Nothing is guessed or dropped.

use crate::error::{IdentifyError, Place};
use dyngen_codegen::model::Model;
use std::fmt::Write as _;
use std::path::Path;

/// Samples of every joint, in the description's joint order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    pub time: Vec<f64>,
    /// `q[k][j]`: sample `k`, joint `j`.
    pub q: Vec<Vec<f64>>,
    pub qd: Option<Vec<Vec<f64>>>,
    pub qdd: Option<Vec<Vec<f64>>>,
    pub tau: Option<Vec<Vec<f64>>>,
    /// The line of each sample in its file (for messages; empty for generated samples).
    pub lines: Vec<usize>,
}

impl Samples {
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
}

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Time,
    Q,
    Qd,
    Qdd,
    Tau,
}

const KINDS: [(&str, Kind); 4] = [
    ("q", Kind::Q),
    ("qd", Kind::Qd),
    ("qdd", Kind::Qdd),
    ("tau", Kind::Tau),
];

fn joint_list(model: &Model) -> String {
    model
        .joints()
        .iter()
        .map(|j| j.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reads a data file for `model`; `require_torque`: `tau[...]` columns must be present.
pub fn read_csv(path: &Path, model: &Model, require_torque: bool) -> Result<Samples, IdentifyError> {
    let file = std::fs::File::open(path).map_err(|source| IdentifyError::Read {
        path: path.to_owned(),
        source,
    })?;
    read_samples(file, model, require_torque).map_err(|e| e.in_file(path))
}

/// The non-blank records of `reader` with their line numbers. Every record may have its own
/// number of fields, so that a short line is reported naming both counts.
fn records(
    reader: impl std::io::Read,
) -> impl Iterator<Item = Result<(usize, csv::StringRecord), IdentifyError>> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(reader)
        .into_records()
        .filter_map(|record| match record {
            Ok(r) if r.len() == 1 && r[0].is_empty() => None,
            Ok(r) => Some(Ok((r.position().map_or(0, |p| p.line() as usize), r))),
            Err(source) => {
                let line = source.position().map(|p| p.line() as usize);
                let place = Place {
                    line,
                    ..Place::default()
                };
                Some(Err(IdentifyError::Csv { place, source }))
            }
        })
}

/// [`read_csv`] on any reader (errors carry line and column; the caller adds the file).
fn read_samples(
    reader: impl std::io::Read,
    model: &Model,
    require_torque: bool,
) -> Result<Samples, IdentifyError> {
    let n = model.dof();
    let mut lines = records(reader);
    let Some(first) = lines.next() else {
        return Err(IdentifyError::data(
            "the file is empty: expected a header line of column names",
        ));
    };
    let (header_line, header) = first?;
    let names: Vec<&str> = header.iter().collect();
    // (kind, joint) of every column; where each (kind, joint) is.
    let mut columns: Vec<(Kind, usize)> = Vec::with_capacity(names.len());
    let mut place: std::collections::HashMap<(u8, usize), usize> = std::collections::HashMap::new();
    for (c, name) in names.iter().enumerate() {
        let err = |msg: String| {
            IdentifyError::data(msg)
                .at_line(header_line)
                .at_column(c + 1, name)
        };
        let (kind, joint) = if *name == "time" {
            (Kind::Time, 0)
        } else {
            let parsed = name
                .strip_suffix(']')
                .and_then(|s| s.split_once('['))
                .and_then(|(k, j)| KINDS.iter().find(|(p, _)| *p == k).map(|&(_, kind)| (kind, j)));
            let Some((kind, joint_name)) = parsed else {
                return Err(err(
                    "unknown column: expected time, q[<joint>], qd[<joint>], qdd[<joint>] or tau[<joint>]"
                        .into(),
                ));
            };
            let Some(joint) = model.joints().iter().position(|j| j.name == joint_name) else {
                return Err(err(format!(
                    "unknown joint '{joint_name}' (the robot's moving joints: {})",
                    joint_list(model)
                )));
            };
            (kind, joint)
        };
        if let Some(first) = place.insert((kind as u8, joint), c) {
            return Err(err(format!("duplicate column (first at column {})", first + 1)));
        }
        columns.push((kind, joint));
    }
    let has = |kind: Kind, j: usize| place.contains_key(&(kind as u8, j));
    if !has(Kind::Time, 0) {
        return Err(IdentifyError::data("missing column 'time'").at_line(header_line));
    }
    let mut required = vec![(Kind::Q, "q", "every joint needs its position")];
    if require_torque {
        required.push((Kind::Tau, "tau", "every joint needs its torque"));
    }
    for (kind, label, why) in required {
        if let Some(j) = (0..n).find(|&j| !has(kind, j)) {
            let msg = format!(
                "missing column '{label}[{}]' for joint '{}' ({why})",
                model.joints()[j].name,
                model.joints()[j].name
            );
            return Err(IdentifyError::data(msg).at_line(header_line));
        }
    }
    for (kind, label) in [(Kind::Qd, "qd"), (Kind::Qdd, "qdd"), (Kind::Tau, "tau")] {
        let given = (0..n).filter(|&j| has(kind, j)).count();
        if given > 0 && given < n {
            let j = (0..n).find(|&j| !has(kind, j)).unwrap_or(0);
            let msg = format!(
                "missing column '{label}[{}]' for joint '{}': {label} is given for some joints, so it must be given for all",
                model.joints()[j].name, model.joints()[j].name
            );
            return Err(IdentifyError::data(msg).at_line(header_line));
        }
    }
    let with = |kind: Kind| has(kind, 0).then(Vec::new);
    let mut samples = Samples {
        qd: with(Kind::Qd),
        qdd: with(Kind::Qdd),
        tau: with(Kind::Tau),
        ..Samples::default()
    };
    for record in lines {
        let (line, fields) = record?;
        if fields.len() != names.len() {
            let msg = format!(
                "{} fields, but the header has {} columns",
                fields.len(),
                names.len()
            );
            return Err(IdentifyError::data(msg).at_line(line));
        }
        let mut row = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let mut time = 0.0;
        for (c, (field, &(kind, j))) in fields.iter().zip(&columns).enumerate() {
            let err = |msg: String| IdentifyError::data(msg).at_line(line).at_column(c + 1, names[c]);
            if field.is_empty() {
                return Err(err("empty field: expected a number".into()));
            }
            let value: f64 = field
                .parse()
                .map_err(|_| err(format!("'{field}' is not a number")))?;
            if !value.is_finite() {
                return Err(err(format!("{field} is not a finite number")));
            }
            match kind {
                Kind::Time => time = value,
                Kind::Q => row[0][j] = value,
                Kind::Qd => row[1][j] = value,
                Kind::Qdd => row[2][j] = value,
                Kind::Tau => row[3][j] = value,
            }
        }
        if let Some(&previous) = samples.time.last() {
            if time <= previous {
                let c = place[&(Kind::Time as u8, 0)];
                let msg = format!(
                    "time {time} does not increase (the sample before, line {}, is at {previous})",
                    samples.lines.last().copied().unwrap_or(0)
                );
                return Err(IdentifyError::data(msg).at_line(line).at_column(c + 1, "time"));
            }
        }
        for (j, joint) in model.joints().iter().enumerate() {
            let Some(l) = joint.limits else { continue };
            let err = |kind: Kind, label: &str, msg: String| {
                let c = place[&(kind as u8, j)];
                IdentifyError::data(format!("joint '{}': {msg}", joint.name))
                    .at_line(line)
                    .at_column(c + 1, &format!("{label}[{}]", joint.name))
            };
            // Limits with a relative slack of 1e-9: printed values round-trip, but a
            // trajectory written at the limit may land a rounding error beyond it.
            let slack = 1e-9 * (l.upper - l.lower).abs().max(1.0);
            let q = row[0][j];
            if q < l.lower - slack || q > l.upper + slack {
                let msg = format!(
                    "position {q} is outside the joint limits [{}, {}]",
                    l.lower, l.upper
                );
                return Err(err(Kind::Q, "q", msg));
            }
            if samples.qd.is_some() && l.velocity > 0.0 && row[1][j].abs() > l.velocity * (1.0 + 1e-9) {
                let msg = format!("velocity {} exceeds the velocity limit {}", row[1][j], l.velocity);
                return Err(err(Kind::Qd, "qd", msg));
            }
        }
        let [q, qd, qdd, tau] = row;
        samples.time.push(time);
        samples.q.push(q);
        if let Some(v) = samples.qd.as_mut() {
            v.push(qd);
        }
        if let Some(v) = samples.qdd.as_mut() {
            v.push(qdd);
        }
        if let Some(v) = samples.tau.as_mut() {
            v.push(tau);
        }
        samples.lines.push(line);
    }
    if samples.is_empty() {
        return Err(IdentifyError::data("no samples: the file has a header line only"));
    }
    Ok(samples)
}

/// The CSV text of `samples` (columns `time`, `q[..]`, then `qd`, `qdd`, `tau` when present).
/// Numbers are written in Rust's shortest round-trip form, so reading gives the same values.
pub fn to_csv(model: &Model, samples: &Samples) -> String {
    let names: Vec<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
    let mut out = String::from("time");
    let blocks: Vec<(&str, &Vec<Vec<f64>>)> = [
        ("q", Some(&samples.q)),
        ("qd", samples.qd.as_ref()),
        ("qdd", samples.qdd.as_ref()),
        ("tau", samples.tau.as_ref()),
    ]
    .into_iter()
    .filter_map(|(l, v)| v.map(|v| (l, v)))
    .collect();
    for (label, _) in &blocks {
        for name in &names {
            let _ = write!(out, ",{label}[{name}]");
        }
    }
    out.push('\n');
    for (k, t) in samples.time.iter().enumerate() {
        let _ = write!(out, "{t}");
        for (_, values) in &blocks {
            for x in &values[k] {
                let _ = write!(out, ",{x}");
            }
        }
        out.push('\n');
    }
    out
}
