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
use dyngen_model::model::Model;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Samples of every joint, in the description's joint order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    pub time: Vec<f64>,
    /// `q[k][j]`: sample `k`, joint `j`.
    pub q: Vec<Vec<f64>>,
    pub qd: Option<Vec<Vec<f64>>>,
    pub qdd: Option<Vec<Vec<f64>>>,
    pub tau: Option<Vec<Vec<f64>>>,
    /// A force/torque sensor's wrench `[f; m]` per sample, in [`Samples::sensor_frame`].
    pub wrench: Option<Vec<[f64; 6]>>,
    /// The frame (of the description) the wrench columns name.
    pub sensor_frame: Option<String>,
    /// The line of each sample in its file (for messages; empty for generated samples).
    pub lines: Vec<usize>,
    /// The file the samples were read from, which errors about them name (`None` for
    /// generated samples).
    pub file: Option<PathBuf>,
}

impl Samples {
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// `e` placed in the file the samples came from, when they came from one.
    /// Samples built in memory (not read by [`read_csv`], which checks each line) checked as
    /// the reader checks a file's: every row has the robot's joints, every number is finite,
    /// and time increases. The first problem is the error, naming the sample (its line, when
    /// the samples know it), the column and the value.
    pub(crate) fn check(&self, model: &Model) -> Result<(), IdentifyError> {
        let n = model.dof();
        let joints = model.joints();
        let place = |k: usize, message: String| {
            let e = IdentifyError::data(message);
            match self.lines.get(k) {
                Some(&line) => e.at_line(line),
                None => IdentifyError::data(format!("sample {k} (t = {} s): {e}", self.time[k])),
            }
        };
        let columns = [
            ("q", Some(&self.q)),
            ("qd", self.qd.as_ref()),
            ("qdd", self.qdd.as_ref()),
            ("tau", self.tau.as_ref()),
        ];
        for (name, rows) in columns.iter().filter_map(|(name, rows)| rows.map(|r| (name, r))) {
            if rows.len() != self.len() {
                return Err(IdentifyError::data(format!(
                    "{} times but {} rows of {name}: every sample needs each",
                    self.len(),
                    rows.len()
                )));
            }
        }
        for k in 0..self.len() {
            if !self.time[k].is_finite() {
                return Err(place(k, format!("time {} is not a finite number", self.time[k])));
            }
            if k > 0 && self.time[k] <= self.time[k - 1] {
                return Err(place(
                    k,
                    format!(
                        "time {} does not increase (the sample before is at {})",
                        self.time[k],
                        self.time[k - 1]
                    ),
                ));
            }
            for (name, rows) in columns.iter().filter_map(|(name, rows)| rows.map(|r| (name, r))) {
                let row = &rows[k];
                if row.len() != n {
                    return Err(place(
                        k,
                        format!("{} values of {name}, the robot has {n} joints", row.len()),
                    ));
                }
                if let Some(j) = row.iter().position(|v| !v.is_finite()) {
                    return Err(place(
                        k,
                        format!("{name}[{}]: {} is not a finite number", joints[j].name, row[j]),
                    ));
                }
            }
            if let Some(w) = self.wrench.as_ref().and_then(|w| w.get(k)) {
                if let Some(c) = w.iter().position(|v| !v.is_finite()) {
                    return Err(place(
                        k,
                        format!(
                            "{}: {} is not a finite number",
                            ["fx", "fy", "fz", "mx", "my", "mz"][c],
                            w[c]
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    pub(crate) fn locate(&self, e: IdentifyError) -> IdentifyError {
        match &self.file {
            Some(file) => e.in_file(file),
            None => e,
        }
    }

    fn push(&mut self, sample: Sample) {
        self.time.push(sample.time);
        self.q.push(sample.q);
        for (all, one) in [
            (&mut self.qd, sample.qd),
            (&mut self.qdd, sample.qdd),
            (&mut self.tau, sample.tau),
        ] {
            if let (Some(all), Some(one)) = (all.as_mut(), one) {
                all.push(one);
            }
        }
        if let (Some(all), Some(one)) = (self.wrench.as_mut(), sample.wrench) {
            all.push(one);
        }
        self.lines.push(sample.line);
    }
}

/// One line of a data file.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    pub line: usize,
    pub time: f64,
    pub q: Vec<f64>,
    pub qd: Option<Vec<f64>>,
    pub qdd: Option<Vec<f64>>,
    pub tau: Option<Vec<f64>>,
    pub wrench: Option<[f64; 6]>,
}

/// What a joint column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
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

/// The six wrench columns of a force/torque sensor, in the order of [`Sample::wrench`].
const WRENCH: [&str; 6] = ["fx", "fy", "fz", "mx", "my", "mz"];

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Column {
    Time,
    Joint(Kind, usize),
    /// Component `k` of [`WRENCH`].
    Wrench(usize),
}

fn joint_list(model: &Model) -> String {
    model
        .joints()
        .iter()
        .map(|j| j.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

fn frame_list(model: &Model) -> String {
    model
        .frames()
        .iter()
        .map(|f| f.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reads a data file for `model`; `require_torque`: `tau[...]` columns must be present.
pub fn read_csv(path: &Path, model: &Model, require_torque: bool) -> Result<Samples, IdentifyError> {
    let reader = SampleReader::open(path, model, require_torque)?;
    let mut samples = reader.empty_samples();
    samples.file = Some(reader.path.clone());
    for sample in reader {
        samples.push(sample?);
    }
    if samples.is_empty() {
        return Err(IdentifyError::data("no samples: the file has a header line only").in_file(path));
    }
    Ok(samples)
}

/// What messages call the standard input, read as the data file `-`.
const STDIN: &str = "<stdin>";

/// Whether `path` is read once only: the standard input (`-`), a pipe, a terminal or another
/// device, which a second read would find used up.
pub(crate) fn read_once(path: &Path) -> bool {
    path == Path::new("-") || std::fs::metadata(path).is_ok_and(|m| !m.is_file())
}

/// A CSV record with its line and byte offset.
type Record = (usize, u64, csv::StringRecord);

/// The non-blank records of `reader` with their line numbers. Every record may have its own
/// number of fields, so that a short line is reported naming both counts. Fields are trimmed
/// where they are read (cheaper than trimming every record).
fn records(reader: impl std::io::Read) -> impl Iterator<Item = Result<Record, IdentifyError>> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(reader)
        .into_records()
        .filter_map(|record| match record {
            Ok(r) if r.len() == 1 && r[0].trim().is_empty() => None,
            Ok(r) => {
                let (line, byte) = r.position().map_or((0, 0), |p| (p.line() as usize, p.byte()));
                Some(Ok((line, byte, r)))
            }
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

/// The header line: what each column holds and where each quantity is.
struct Header {
    names: Vec<String>,
    columns: Vec<Column>,
    place: HashMap<Column, usize>,
    n: usize,
    sensor_frame: Option<String>,
    /// Whether each [`Kind`] has columns (looked up once, not per line).
    given: [bool; 4],
}

impl Header {
    fn parse(
        line: usize,
        record: &csv::StringRecord,
        model: &Model,
        require_torque: bool,
    ) -> Result<Header, IdentifyError> {
        let n = model.dof();
        let names: Vec<String> = record.iter().map(|f| f.trim().to_owned()).collect();
        let mut columns = Vec::with_capacity(names.len());
        let mut place: HashMap<Column, usize> = HashMap::new();
        let mut sensor: Option<(String, usize)> = None;
        for (c, name) in names.iter().enumerate() {
            let err = |msg: String| IdentifyError::data(msg).at_line(line).at_column(c + 1, name);
            let bracketed = name.strip_suffix(']').and_then(|s| s.split_once('['));
            let column = if name == "time" {
                Column::Time
            } else if let Some(k) = WRENCH.iter().position(|w| w == name) {
                return Err(err(format!(
                    "'{}' names no frame: a force/torque column is {}[<frame>], with the frame of \
                     the description the sensor measures in (the robot's frames: {})",
                    WRENCH[k],
                    WRENCH[k],
                    frame_list(model)
                )));
            } else if let Some((label, frame)) = bracketed.filter(|(label, _)| WRENCH.contains(label)) {
                if !model.frames().iter().any(|f| f.name == frame) {
                    return Err(err(format!(
                        "unknown frame '{frame}' (the robot's frames: {}; name others with `frames:` in the description)",
                        frame_list(model)
                    )));
                }
                match &sensor {
                    Some((first, at)) if first != frame => {
                        return Err(err(format!(
                            "a second force/torque frame '{frame}' (column {} names '{first}'): one sensor per file",
                            at + 1
                        )))
                    }
                    Some(_) => {}
                    None => sensor = Some((frame.to_owned(), c)),
                }
                Column::Wrench(WRENCH.iter().position(|w| *w == label).expect("a wrench label"))
            } else {
                let parsed = bracketed
                    .and_then(|(k, j)| KINDS.iter().find(|(p, _)| *p == k).map(|&(_, kind)| (kind, j)));
                let Some((kind, joint_name)) = parsed else {
                    return Err(err(
                        "unknown column: expected time, q[<joint>], qd[<joint>], qdd[<joint>], tau[<joint>] \
                         or a force/torque sensor's fx, fy, fz, mx, my, mz[<frame>]"
                            .into(),
                    ));
                };
                let Some(joint) = model.joints().iter().position(|j| j.name == joint_name) else {
                    return Err(err(format!(
                        "unknown joint '{joint_name}' (the robot's moving joints: {})",
                        joint_list(model)
                    )));
                };
                Column::Joint(kind, joint)
            };
            if let Some(first) = place.insert(column, c) {
                return Err(err(format!("duplicate column (first at column {})", first + 1)));
            }
            columns.push(column);
        }
        let has = |column: Column| place.contains_key(&column);
        if !has(Column::Time) {
            return Err(IdentifyError::data("missing column 'time'").at_line(line));
        }
        let mut required = vec![(Kind::Q, "q", "every joint needs its position")];
        if require_torque {
            required.push((Kind::Tau, "tau", "every joint needs its torque"));
        }
        for (kind, label, why) in required {
            if let Some(j) = (0..n).find(|&j| !has(Column::Joint(kind, j))) {
                let name = &model.joints()[j].name;
                let msg = format!("missing column '{label}[{name}]' for joint '{name}' ({why})");
                return Err(IdentifyError::data(msg).at_line(line));
            }
        }
        for (kind, label) in [(Kind::Qd, "qd"), (Kind::Qdd, "qdd"), (Kind::Tau, "tau")] {
            let given = (0..n).filter(|&j| has(Column::Joint(kind, j))).count();
            if given > 0 && given < n {
                let j = (0..n).find(|&j| !has(Column::Joint(kind, j))).unwrap_or(0);
                let name = &model.joints()[j].name;
                let msg = format!(
                    "missing column '{label}[{name}]' for joint '{name}': {label} is given for some joints, so it must be given for all",
                );
                return Err(IdentifyError::data(msg).at_line(line));
            }
        }
        if let Some((frame, _)) = &sensor {
            if let Some(k) = (0..6).find(|&k| !has(Column::Wrench(k))) {
                let msg = format!(
                    "missing column '{}[{frame}]': a force/torque sensor needs all six of fx, fy, fz, mx, my, mz",
                    WRENCH[k]
                );
                return Err(IdentifyError::data(msg).at_line(line));
            }
        }
        let given = [Kind::Q, Kind::Qd, Kind::Qdd, Kind::Tau].map(|kind| has(Column::Joint(kind, 0)));
        Ok(Header {
            names,
            columns,
            place,
            n,
            sensor_frame: sensor.map(|(frame, _)| frame),
            given,
        })
    }

    fn has(&self, kind: Kind) -> bool {
        self.given[kind as usize]
    }

    /// The number in field `c` of `line`, or the error that names it.
    fn number(&self, line: usize, c: usize, field: &str) -> Result<f64, IdentifyError> {
        let err = |msg: String| {
            IdentifyError::data(msg)
                .at_line(line)
                .at_column(c + 1, &self.names[c])
        };
        let field = field.trim();
        if field.is_empty() {
            return Err(err("empty field: expected a number".into()));
        }
        let value: f64 = field
            .parse()
            .map_err(|_| err(format!("'{field}' is not a number")))?;
        if !value.is_finite() {
            return Err(err(format!("{field} is not a finite number")));
        }
        Ok(value)
    }

    /// The sample on one line, checked against the joint limits.
    fn sample(
        &self,
        line: usize,
        fields: &csv::StringRecord,
        model: &Model,
    ) -> Result<Sample, IdentifyError> {
        let n = self.n;
        if fields.len() != self.names.len() {
            let msg = format!(
                "{} fields, but the header has {} columns",
                fields.len(),
                self.names.len()
            );
            return Err(IdentifyError::data(msg).at_line(line));
        }
        let mut row = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let mut wrench = [0.0; 6];
        let mut time = 0.0;
        for (c, (field, column)) in fields.iter().zip(&self.columns).enumerate() {
            let value = self.number(line, c, field)?;
            match *column {
                Column::Time => time = value,
                Column::Joint(kind, j) => row[kind as usize][j] = value,
                Column::Wrench(k) => wrench[k] = value,
            }
        }
        for (j, joint) in model.joints().iter().enumerate() {
            let Some(l) = joint.limits else { continue };
            let err = |kind: Kind, label: &str, msg: String| {
                let c = self.place[&Column::Joint(kind, j)];
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
            if self.has(Kind::Qd) && l.velocity > 0.0 && row[1][j].abs() > l.velocity * (1.0 + 1e-9) {
                let msg = format!("velocity {} exceeds the velocity limit {}", row[1][j], l.velocity);
                return Err(err(Kind::Qd, "qd", msg));
            }
        }
        let [q, qd, qdd, tau] = row;
        Ok(Sample {
            line,
            time,
            q,
            qd: self.has(Kind::Qd).then_some(qd),
            qdd: self.has(Kind::Qdd).then_some(qdd),
            tau: self.has(Kind::Tau).then_some(tau),
            wrench: self.sensor_frame.as_ref().map(|_| wrench),
        })
    }
}

/// A data file read one line at a time, with every check [`read_csv`] makes (which reads
/// through it): memory that does not depend on the file's length, for logs too long to hold.
/// Yields each sample, or the first error, which names the file, line and column.
pub struct SampleReader<'m> {
    model: &'m Model,
    header: Header,
    records: Box<dyn Iterator<Item = Result<Record, IdentifyError>>>,
    path: PathBuf,
    previous: Option<(f64, usize)>,
    bytes: u64,
    failed: bool,
}

impl<'m> SampleReader<'m> {
    /// Opens `path` and reads its header line. `-` is the standard input (named `<stdin>` in
    /// messages).
    pub fn open(
        path: &Path,
        model: &'m Model,
        require_torque: bool,
    ) -> Result<SampleReader<'m>, IdentifyError> {
        if path == Path::new("-") {
            return SampleReader::from_reader(std::io::stdin(), Path::new(STDIN), model, require_torque);
        }
        let file = std::fs::File::open(path).map_err(|source| IdentifyError::Read {
            path: path.to_owned(),
            source,
        })?;
        SampleReader::from_reader(file, path, model, require_torque)
    }

    /// Reads the header line of the data `reader` gives, which messages call `path`.
    pub fn from_reader(
        reader: impl std::io::Read + 'static,
        path: &Path,
        model: &'m Model,
        require_torque: bool,
    ) -> Result<SampleReader<'m>, IdentifyError> {
        let mut records = records(std::io::BufReader::with_capacity(1 << 16, reader));
        let Some(first) = records.next() else {
            return Err(
                IdentifyError::data("the file is empty: expected a header line of column names")
                    .in_file(path),
            );
        };
        let (line, _, header) = first.map_err(|e| e.in_file(path))?;
        let header = Header::parse(line, &header, model, require_torque).map_err(|e| e.in_file(path))?;
        Ok(SampleReader {
            model,
            header,
            records: Box::new(records),
            path: path.to_owned(),
            previous: None,
            bytes: 0,
            failed: false,
        })
    }

    /// Samples with the columns this file has, and none yet.
    pub fn empty_samples(&self) -> Samples {
        let with = |kind: Kind| self.header.has(kind).then(Vec::new);
        Samples {
            qd: with(Kind::Qd),
            qdd: with(Kind::Qdd),
            tau: with(Kind::Tau),
            wrench: self.header.sensor_frame.as_ref().map(|_| Vec::new()),
            sensor_frame: self.header.sensor_frame.clone(),
            ..Samples::default()
        }
    }

    pub fn has_velocities(&self) -> bool {
        self.header.has(Kind::Qd)
    }

    pub fn has_accelerations(&self) -> bool {
        self.header.has(Kind::Qdd)
    }

    /// Bytes of the file read so far (for progress).
    pub fn bytes_read(&self) -> u64 {
        self.bytes
    }

    /// The time of the next line, read without its other fields (a first pass over a long
    /// file); `Some(None)` when that line is not plainly a later sample (a reader that reads
    /// every field says what is wrong with it).
    pub(crate) fn next_time(&mut self) -> Option<Option<f64>> {
        let Ok((line, byte, fields)) = self.records.next()? else {
            return Some(None);
        };
        self.bytes = byte;
        let c = self.header.place[&Column::Time];
        if fields.len() != self.header.names.len() {
            return Some(None);
        }
        let time = self.header.number(line, c, &fields[c]).ok()?;
        if self.previous.is_some_and(|(previous, _)| time <= previous) {
            return Some(None);
        }
        self.previous = Some((time, line));
        Some(Some(time))
    }

    fn next_sample(&mut self) -> Option<Result<Sample, IdentifyError>> {
        let (line, byte, fields) = match self.records.next()? {
            Ok(record) => record,
            Err(e) => return Some(Err(e)),
        };
        self.bytes = byte;
        let sample = match self.header.sample(line, &fields, self.model) {
            Ok(sample) => sample,
            Err(e) => return Some(Err(e)),
        };
        if let Some((previous, previous_line)) = self.previous {
            if sample.time <= previous {
                let c = self.header.place[&Column::Time];
                let msg = format!(
                    "time {} does not increase (the sample before, line {previous_line}, is at {previous})",
                    sample.time
                );
                return Some(Err(IdentifyError::data(msg)
                    .at_line(line)
                    .at_column(c + 1, "time")));
            }
        }
        self.previous = Some((sample.time, line));
        Some(Ok(sample))
    }
}

impl Iterator for SampleReader<'_> {
    type Item = Result<Sample, IdentifyError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let next = self.next_sample()?;
        if next.is_err() {
            self.failed = true;
        }
        Some(next.map_err(|e| e.in_file(&self.path)))
    }
}

/// The CSV text of `samples` (columns `time`, `q[..]`, then `qd`, `qdd`, `tau` and the
/// wrench when present). Numbers are written in Rust's shortest round-trip form, so reading
/// gives the same values.
pub fn to_csv(model: &Model, samples: &Samples) -> String {
    let mut out = Vec::new();
    let mut writer = SampleWriter::new(&mut out, model, &samples.empty_like()).expect("writing to memory");
    for k in 0..samples.len() {
        writer.write(&samples.sample(k)).expect("writing to memory");
    }
    drop(writer);
    String::from_utf8(out).expect("CSV text is UTF-8")
}

impl Samples {
    /// Sample `k`.
    pub fn sample(&self, k: usize) -> Sample {
        Sample {
            line: self.lines.get(k).copied().unwrap_or(0),
            time: self.time[k],
            q: self.q[k].clone(),
            qd: self.qd.as_ref().map(|v| v[k].clone()),
            qdd: self.qdd.as_ref().map(|v| v[k].clone()),
            tau: self.tau.as_ref().map(|v| v[k].clone()),
            wrench: self.wrench.as_ref().map(|v| v[k]),
        }
    }

    /// No samples, the same columns.
    fn empty_like(&self) -> Samples {
        Samples {
            qd: self.qd.as_ref().map(|_| Vec::new()),
            qdd: self.qdd.as_ref().map(|_| Vec::new()),
            tau: self.tau.as_ref().map(|_| Vec::new()),
            wrench: self.wrench.as_ref().map(|_| Vec::new()),
            sensor_frame: self.sensor_frame.clone(),
            ..Samples::default()
        }
    }
}

/// Writes a data file one sample at a time (the way back of [`SampleReader`]): the columns of
/// `like` (which of `qd`, `qdd`, `tau` and a wrench it has), every sample given must have them.
pub struct SampleWriter<W: std::io::Write> {
    out: std::io::BufWriter<W>,
    line: String,
}

impl<W: std::io::Write> SampleWriter<W> {
    /// Writes the header line.
    pub fn new(out: W, model: &Model, like: &Samples) -> std::io::Result<SampleWriter<W>> {
        let mut header = String::from("time");
        let mut blocks = vec!["q"];
        for (label, given) in [
            ("qd", like.qd.is_some()),
            ("qdd", like.qdd.is_some()),
            ("tau", like.tau.is_some()),
        ] {
            if given {
                blocks.push(label);
            }
        }
        for label in blocks {
            for joint in model.joints() {
                let _ = write!(header, ",{label}[{}]", joint.name);
            }
        }
        if let (Some(_), Some(frame)) = (&like.wrench, &like.sensor_frame) {
            for label in WRENCH {
                let _ = write!(header, ",{label}[{frame}]");
            }
        }
        header.push('\n');
        let mut out = std::io::BufWriter::new(out);
        out.write_all(header.as_bytes())?;
        Ok(SampleWriter {
            out,
            line: String::new(),
        })
    }

    /// Writes one sample's line.
    pub fn write(&mut self, sample: &Sample) -> std::io::Result<()> {
        self.line.clear();
        let _ = write!(self.line, "{}", sample.time);
        let joints = [
            Some(&sample.q),
            sample.qd.as_ref(),
            sample.qdd.as_ref(),
            sample.tau.as_ref(),
        ];
        for x in joints.into_iter().flatten().flatten() {
            let _ = write!(self.line, ",{x}");
        }
        for x in sample.wrench.iter().flatten() {
            let _ = write!(self.line, ",{x}");
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())
    }
}
