//! The control law's gains as a person writes them: a small CSV file, or `JOINT=KP,KD[,KI]`
//! assignments; every joint by name, each once, every problem one error with its place.
//!
//! ```text
//! joint,kp,kd,ki
//! shoulder,2000,120,0
//! elbow,1500,90,0
//! ```
//!
//! `ki` is optional (a PD law); columns in any order.

use crate::closed_loop::{ControlLaw, JointGains};
use crate::error::IdentifyError;
use dyngen_model::model::Model;
use std::path::Path;

/// Gains collected joint by joint, each once.
struct Table<'m> {
    model: &'m Model,
    gains: Vec<Option<JointGains>>,
}

impl<'m> Table<'m> {
    fn new(model: &'m Model) -> Table<'m> {
        Table {
            model,
            gains: vec![None; model.dof()],
        }
    }

    /// Sets joint `name`'s gains; an error for an unknown joint or one given twice.
    fn set(&mut self, name: &str, gains: JointGains) -> Result<(), IdentifyError> {
        let joints = self.model.joints();
        let Some(j) = joints.iter().position(|joint| joint.name == name) else {
            let names: Vec<&str> = joints.iter().map(|joint| joint.name.as_str()).collect();
            return Err(IdentifyError::data(format!(
                "unknown joint '{name}' (the robot's moving joints: {})",
                names.join(", ")
            )));
        };
        if self.gains[j].replace(gains).is_some() {
            return Err(IdentifyError::data(format!("joint '{name}' has gains twice")));
        }
        Ok(())
    }

    /// The law, when every joint has gains.
    fn finished(self) -> Result<ControlLaw, IdentifyError> {
        let missing: Vec<&str> = self
            .model
            .joints()
            .iter()
            .zip(&self.gains)
            .filter(|(_, g)| g.is_none())
            .map(|(joint, _)| joint.name.as_str())
            .collect();
        if !missing.is_empty() {
            return Err(IdentifyError::data(format!(
                "no gains for joint{} {} (every joint needs kp and kd)",
                if missing.len() > 1 { "s" } else { "" },
                missing.join(", ")
            )));
        }
        let law = ControlLaw {
            gains: self.gains.into_iter().map(|g| g.expect("checked")).collect(),
        };
        law.check(self.model)?;
        Ok(law)
    }
}

/// A gain written `text`: a finite number.
fn number(text: &str, what: &str) -> Result<f64, IdentifyError> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| IdentifyError::data(format!("{what} '{}' is not a finite number", text.trim())))
}

impl ControlLaw {
    /// The gains of the CSV file `path` (`joint,kp,kd[,ki]`, a line per joint of `model`).
    pub fn read_csv(path: &Path, model: &Model) -> Result<ControlLaw, IdentifyError> {
        let text = std::fs::read_to_string(path).map_err(|source| IdentifyError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        ControlLaw::from_csv(&text, model).map_err(|e| e.in_file(path))
    }

    /// The gains of CSV text (see [`ControlLaw::read_csv`]).
    pub fn from_csv(text: &str, model: &Model) -> Result<ControlLaw, IdentifyError> {
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .trim(csv::Trim::All)
            .from_reader(text.trim_start_matches('\u{feff}').as_bytes());
        let mut records = reader.records();
        let header = match records.next() {
            Some(Ok(h)) => h,
            Some(Err(source)) => {
                return Err(IdentifyError::data(format!("not valid CSV: {source}")).at_line(1))
            }
            None => return Err(IdentifyError::data("no gains: the file is empty")),
        };
        let mut columns = [None; 4];
        for (c, name) in header.iter().enumerate() {
            let slot = ["joint", "kp", "kd", "ki"]
                .iter()
                .position(|k| *k == name)
                .ok_or_else(|| {
                    IdentifyError::data(format!(
                        "column {} ('{name}'): unknown column: expected joint, kp, kd and optionally ki",
                        c + 1
                    ))
                    .at_line(1)
                })?;
            if columns[slot].replace(c).is_some() {
                return Err(
                    IdentifyError::data(format!("column {} ('{name}'): duplicate column", c + 1)).at_line(1),
                );
            }
        }
        for (slot, name) in [(0, "joint"), (1, "kp"), (2, "kd")] {
            if columns[slot].is_none() {
                return Err(IdentifyError::data(format!("missing column '{name}'")).at_line(1));
            }
        }
        let mut table = Table::new(model);
        for record in records {
            let record = record.map_err(|source| IdentifyError::data(format!("not valid CSV: {source}")))?;
            let line = record.position().map_or(0, |p| p.line() as usize);
            if record.iter().all(str::is_empty) {
                continue;
            }
            let field = |slot: usize| columns[slot].and_then(|c| record.get(c)).unwrap_or("");
            let gains = (|| {
                Ok(JointGains {
                    kp: number(field(1), "kp")?,
                    kd: number(field(2), "kd")?,
                    ki: match columns[3] {
                        Some(_) => number(field(3), "ki")?,
                        None => 0.0,
                    },
                })
            })()
            .and_then(|gains| table.set(field(0), gains));
            gains.map_err(|e| e.at_line(line))?;
        }
        table.finished()
    }

    /// The gains of assignments `JOINT=KP,KD[,KI]`, one per joint of `model`.
    pub fn from_assignments(assignments: &[String], model: &Model) -> Result<ControlLaw, IdentifyError> {
        let mut table = Table::new(model);
        for assignment in assignments {
            let located = |e: IdentifyError| IdentifyError::data(format!("gains '{assignment}': {e}"));
            let (joint, values) = assignment.split_once('=').ok_or_else(|| {
                IdentifyError::data(format!(
                    "gains '{assignment}': expected JOINT=KP,KD or JOINT=KP,KD,KI"
                ))
            })?;
            let values: Vec<&str> = values.split(',').collect();
            if !(2..=3).contains(&values.len()) {
                return Err(IdentifyError::data(format!(
                    "gains '{assignment}': expected JOINT=KP,KD or JOINT=KP,KD,KI"
                )));
            }
            let gains = JointGains {
                kp: number(values[0], "kp").map_err(located)?,
                kd: number(values[1], "kd").map_err(located)?,
                ki: values
                    .get(2)
                    .map_or(Ok(0.0), |v| number(v, "ki"))
                    .map_err(located)?,
            };
            table.set(joint.trim(), gains).map_err(located)?;
        }
        table.finished()
    }
}
