//! `benchmarks/results.csv`: every recorded benchmark measurement, one row each, which
//! `cargo xtask bench-render` turns into the tables of BENCHMARKS.md.
//!
//! Columns, in this order (a header row names them):
//!
//! | column | what |
//! |---|---|
//! | `machine` | the kind of machine, e.g. `AMD EPYC Zen 3 (AVX2)`: one table of BENCHMARKS.md each |
//! | `date` | the day of the run, `YYYY-MM-DD` |
//! | `build` | dyngen's build: `native` (`-C target-cpu=native`) or `default` (no `target-cpu`) |
//! | `robot` | the committed robot (`robots/<robot>.yaml`), or a robot timed outside the repository |
//! | `function` | the benchmark's name for it (criterion group: `fk`, `mass_matrix`, `rnea`, …) |
//! | `frame` | the named frame of the frame functions, else empty |
//! | `form` | `value` (returns a fresh result), `into` (writes into a kept `ResultBuffer`), `lanes4`, `lanes8` (states per call) |
//! | `dyngen_ns` | dyngen's median, ns per call |
//! | `pinocchio_ns` | numeric Pinocchio's median in the same run, ns (empty: not measured) |
//! | `cppadcg_ns` | Pinocchio + CppADCodeGen's median in the same run, ns (empty: not measured) |
//! | `code_kb` | the function's machine code in the native build, KB (empty: not measured) |
//! | `l1i_kib` | the machine's level-1 instruction cache, KiB (empty: unknown) |
//!
//! One file for every run, appended to, rather than a file per run: a run is its rows (they carry
//! its machine and date), a new run supersedes an older one row by row (the renderer shows, per
//! machine, robot, function, frame, form and build, the latest date, and on the same date the row
//! further down), so a partial rerun (one robot, one build) replaces just what it measured, and
//! the history stays in the file where `git log -p` and a spreadsheet can read it.

use std::fmt::Write as _;
use std::path::Path;

/// The header row, which is also the column order.
pub const HEADER: [&str; 12] = [
    "machine",
    "date",
    "build",
    "robot",
    "function",
    "frame",
    "form",
    "dyngen_ns",
    "pinocchio_ns",
    "cppadcg_ns",
    "code_kb",
    "l1i_kib",
];

/// dyngen's build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Build {
    /// No `target-cpu`: run-time dispatch to AVX2/FMA or AVX-512 copies.
    Default,
    /// `RUSTFLAGS="-C target-cpu=native"`, as the anchors are built.
    Native,
}

impl Build {
    pub fn name(self) -> &'static str {
        match self {
            Build::Default => "default",
            Build::Native => "native",
        }
    }
}

/// How the call returns its result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Form {
    /// A fresh result returned by value.
    Value,
    /// Written into a `ResultBuffer` kept between calls.
    Into,
    /// That many states per call, in SIMD lanes (the time is per call).
    Lanes(u32),
}

impl Form {
    fn parse(s: &str) -> Option<Form> {
        match s {
            "value" => Some(Form::Value),
            "into" => Some(Form::Into),
            _ => s
                .strip_prefix("lanes")?
                .parse()
                .ok()
                .filter(|&n| n > 1)
                .map(Form::Lanes),
        }
    }

    fn name(self) -> String {
        match self {
            Form::Value => "value".to_owned(),
            Form::Into => "into".to_owned(),
            Form::Lanes(n) => format!("lanes{n}"),
        }
    }
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub machine: String,
    pub date: String,
    pub build: Build,
    pub robot: String,
    pub function: String,
    pub frame: String,
    pub form: Form,
    pub dyngen_ns: f64,
    pub pinocchio_ns: Option<f64>,
    pub cppadcg_ns: Option<f64>,
    pub code_kb: Option<f64>,
    pub l1i_kib: Option<f64>,
}

impl Row {
    /// What a later row of the same machine replaces.
    pub fn key(&self) -> (&str, &str, &str, Form, Build) {
        (&self.robot, &self.function, &self.frame, self.form, self.build)
    }
}

fn is_date(s: &str) -> bool {
    let b = s.as_bytes();
    b.len() == 10
        && b[4] == b'-'
        && b[7] == b'-'
        && b.iter()
            .enumerate()
            .all(|(i, c)| i == 4 || i == 7 || c.is_ascii_digit())
}

/// The rows of a results file, checked (the header, every field's format).
pub fn parse(text: &str) -> Result<Vec<Row>, String> {
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| e.to_string())?;
    if header.iter().ne(HEADER) {
        return Err(format!(
            "header is `{}`, expected `{}`",
            header.iter().collect::<Vec<_>>().join(","),
            HEADER.join(",")
        ));
    }
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| e.to_string())?;
        let line = record.position().map_or(0, |p| p.line());
        let field = |i: usize| record.get(i).unwrap_or("").trim();
        let bad = |i: usize, what: &str| format!("line {line}: {} `{}`: {what}", HEADER[i], field(i));
        let number = |i: usize| -> Result<Option<f64>, String> {
            match field(i) {
                "" => Ok(None),
                s => match s.parse::<f64>() {
                    Ok(x) if x.is_finite() && x > 0.0 => Ok(Some(x)),
                    _ => Err(bad(i, "not a positive number")),
                },
            }
        };
        let text = |i: usize| -> Result<String, String> {
            match field(i) {
                "" => Err(bad(i, "empty")),
                s => Ok(s.to_owned()),
            }
        };
        if !is_date(field(1)) {
            return Err(bad(1, "not a date YYYY-MM-DD"));
        }
        let build = match field(2) {
            "native" => Build::Native,
            "default" => Build::Default,
            _ => return Err(bad(2, "expected native or default")),
        };
        rows.push(Row {
            machine: text(0)?,
            date: field(1).to_owned(),
            build,
            robot: text(3)?,
            function: text(4)?,
            frame: field(5).to_owned(),
            form: Form::parse(field(6)).ok_or_else(|| bad(6, "expected value, into or lanesN"))?,
            dyngen_ns: number(7)?.ok_or_else(|| bad(7, "empty"))?,
            pinocchio_ns: number(8)?,
            cppadcg_ns: number(9)?,
            code_kb: number(10)?,
            l1i_kib: number(11)?,
        });
    }
    Ok(rows)
}

/// Reads and checks a results file.
pub fn read(path: &Path) -> Result<Vec<Row>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Appends rows to a results file, with the header first when the file is new or empty.
pub fn append(path: &Path, rows: &[Row]) -> Result<(), String> {
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let existing = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(e) => return Err(at(&e)),
    };
    if !existing.trim().is_empty() {
        parse(&existing).map_err(|e| at(&e))?;
    }
    let mut writer = csv::WriterBuilder::new().from_writer(Vec::new());
    if existing.trim().is_empty() {
        writer.write_record(HEADER).map_err(|e| at(&e))?;
    }
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x}"));
    for r in rows {
        writer
            .write_record([
                r.machine.clone(),
                r.date.clone(),
                r.build.name().to_owned(),
                r.robot.clone(),
                r.function.clone(),
                r.frame.clone(),
                r.form.name(),
                format!("{}", r.dyngen_ns),
                opt(r.pinocchio_ns),
                opt(r.cppadcg_ns),
                opt(r.code_kb),
                opt(r.l1i_kib),
            ])
            .map_err(|e| at(&e))?;
    }
    let bytes = writer.into_inner().map_err(|e| at(&e))?;
    let mut text = existing;
    if !text.is_empty() && !text.ends_with('\n') {
        text.push('\n');
    }
    text.push_str(&String::from_utf8_lossy(&bytes));
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| at(&e))?;
    }
    std::fs::write(path, text).map_err(|e| at(&e))
}

/// The rows of one machine that no later row replaces (a later date, or the same date further
/// down the file), in file order.
pub fn latest<'a>(rows: &'a [Row], machine: &str) -> Vec<&'a Row> {
    let mut kept: Vec<&Row> = Vec::new();
    for row in rows.iter().filter(|r| r.machine == machine) {
        match kept.iter().position(|k| k.key() == row.key()) {
            Some(i) if kept[i].date > row.date => {}
            Some(i) => {
                kept.remove(i);
                kept.push(row);
            }
            None => kept.push(row),
        }
    }
    kept
}

/// Today's date (UTC) as `YYYY-MM-DD`, for a new run's rows.
pub fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    civil_date((secs / 86_400) as i64)
}

/// The proleptic Gregorian date `days` after 1970-01-01 (H. Hinnant's `civil_from_days`).
fn civil_date(days: i64) -> String {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    let mut out = String::new();
    let _ = write!(out, "{year:04}-{month:02}-{day:02}");
    out
}

/// Checks a date given on the command line.
pub fn check_date(date: &str) -> Result<(), String> {
    if is_date(date) {
        Ok(())
    } else {
        Err(format!("--date `{date}`: expected YYYY-MM-DD"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str =
        "machine,date,build,robot,function,frame,form,dyngen_ns,pinocchio_ns,cppadcg_ns,code_kb,l1i_kib
M,2026-01-01,native,panda,fk,,value,30,200,90,0.6,32
M,2026-01-02,native,panda,fk,,value,25,210,,0.6,32
M,2026-01-01,default,panda,fk,,value,31,200,90,,32
N,2026-03-01,native,panda,fk,,value,99,,,,
";

    #[test]
    fn parses_and_keeps_the_latest_row_per_key() {
        let rows = parse(SAMPLE).unwrap();
        assert_eq!(rows.len(), 4);
        assert_eq!(rows[1].cppadcg_ns, None);
        let m = latest(&rows, "M");
        // The native row of 2026-01-02 replaces that of 2026-01-01; the default row stays; the
        // other machine's row is not M's.
        assert_eq!(m.len(), 2);
        assert_eq!((m[0].date.as_str(), m[0].dyngen_ns), ("2026-01-02", 25.0));
        assert_eq!(m[1].build, Build::Default);
    }

    #[test]
    fn same_date_keeps_the_later_row_and_an_older_date_never_replaces() {
        let mut rows = parse(SAMPLE).unwrap();
        let mut again = rows[1].clone();
        again.dyngen_ns = 24.0;
        rows.push(again);
        let mut older = rows[1].clone();
        older.date = "2025-12-31".to_owned();
        rows.push(older);
        let m = latest(&rows, "M");
        assert_eq!(m.iter().map(|r| r.dyngen_ns).collect::<Vec<_>>(), [31.0, 24.0]);
        assert_eq!(m[1].date, "2026-01-02");
    }

    #[test]
    fn rejects_bad_fields_with_their_line() {
        let bad = SAMPLE.replace("2026-01-02,native", "2026-1-2,native");
        assert!(parse(&bad).unwrap_err().contains("line 3: date"));
        let bad = SAMPLE.replace(",value,30,", ",byvalue,30,");
        assert!(parse(&bad).unwrap_err().contains("form"));
        let bad = SAMPLE.replace("machine,date", "kind,date");
        assert!(parse(&bad).unwrap_err().contains("header"));
    }

    #[test]
    fn appends_after_the_header() {
        let dir = std::env::temp_dir().join(format!("xtask-results-{}", std::process::id()));
        let path = dir.join("results.csv");
        let _ = std::fs::remove_file(&path);
        let rows = parse(SAMPLE).unwrap();
        append(&path, &rows[..2]).unwrap();
        append(&path, &rows[2..]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(parse(&text).unwrap(), rows);
        assert_eq!(text.matches("machine,date").count(), 1);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn civil_dates() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(20_819), "2027-01-01");
    }
}
