//! `cargo xtask bench-table`: the medians of the last `cargo bench --bench dynamics` run as a
//! Markdown table, generated beside generic, with their ratio; with `--record`, every generated
//! benchmark of that run appended to the results file as rows of a machine ([`crate::results`]).

use crate::results::{Build, Form, Row};
use std::collections::BTreeMap;
use std::path::Path;

/// Median in nanoseconds of one criterion benchmark, if it ran.
fn median_ns(dir: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(dir.join("new/estimates.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    json["median"]["point_estimate"].as_f64()
}

/// Criterion's `group_id` of one benchmark ("robot/quantity"), if it ran.
fn group_id(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join("new/benchmark.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    json["group_id"].as_str().map(str::to_owned)
}

fn groups(criterion: &Path) -> Result<std::fs::ReadDir, String> {
    std::fs::read_dir(criterion).map_err(|e| {
        format!(
            "{}: {e} (run `cargo bench --bench dynamics` first)",
            criterion.display()
        )
    })
}

/// Rows `robot → quantity → (generated, generic)` from `target/criterion`.
pub fn table(criterion: &Path) -> Result<String, String> {
    let mut rows: BTreeMap<(String, String), (Option<f64>, Option<f64>)> = BTreeMap::new();
    // Criterion names a group "robot/quantity" directory "robot_quantity"; robot names have
    // underscores too (panda_rounded), so the split comes from the group id it records.
    for entry in groups(criterion)?.flatten() {
        let group = entry.file_name().to_string_lossy().into_owned();
        let (generated_dir, generic_dir) = (entry.path().join("generated"), entry.path().join("generic"));
        let id = group_id(&generated_dir).or_else(|| group_id(&generic_dir));
        let Some((robot, quantity)) = id
            .as_deref()
            .and_then(|id| id.split_once('/'))
            .or_else(|| group.split_once('_'))
        else {
            continue;
        };
        let generated = median_ns(&generated_dir);
        let generic = median_ns(&generic_dir);
        if generated.is_some() || generic.is_some() {
            rows.insert((robot.to_owned(), quantity.to_owned()), (generated, generic));
        }
    }
    let fmt = |x: Option<f64>| x.map_or("–".to_owned(), |x| format!("{x:.0}"));
    let mut out = String::from(
        "| robot | quantity | generated (ns) | generic (ns) | generic / generated |\n|---|---|---:|---:|---:|\n",
    );
    for ((robot, quantity), (generated, generic)) in rows {
        let ratio = match (generated, generic) {
            (Some(a), Some(b)) => format!("{:.1}×", b / a),
            _ => "–".to_owned(),
        };
        out += &format!(
            "| {robot} | {quantity} | {} | {} | {ratio} |\n",
            fmt(generated),
            fmt(generic)
        );
    }
    Ok(out)
}

/// The form a criterion id of the generated benches times: `generated`, `generated_into`,
/// `generated_lanes4`, … (the generic dynamics' `generic` is not recorded).
fn form(id: &str) -> Option<Form> {
    match id.strip_prefix("generated")? {
        "" => Some(Form::Value),
        "_into" => Some(Form::Into),
        lanes => lanes
            .strip_prefix("_lanes")?
            .parse()
            .ok()
            .filter(|&n| n > 1)
            .map(Form::Lanes),
    }
}

/// Every generated benchmark of `target/criterion` as a results row (no anchors: `cargo bench`
/// times dyngen alone), sorted by robot, function and form.
pub fn records(criterion: &Path, machine: &str, build: Build, date: &str) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    for group in groups(criterion)?.flatten() {
        let Ok(benches) = std::fs::read_dir(group.path()) else {
            continue;
        };
        for bench in benches.flatten() {
            let dir = bench.path();
            let (Some(id), Some(form), Some(ns)) = (
                group_id(&dir),
                form(&bench.file_name().to_string_lossy()),
                median_ns(&dir),
            ) else {
                continue;
            };
            // "robot/function" or, for a named frame, "robot/function/frame".
            let mut parts = id.splitn(3, '/');
            let (Some(robot), Some(function)) = (parts.next(), parts.next()) else {
                continue;
            };
            rows.push(Row {
                machine: machine.to_owned(),
                date: date.to_owned(),
                build,
                robot: robot.to_owned(),
                function: function.to_owned(),
                frame: parts.next().unwrap_or("").to_owned(),
                form,
                dyngen_ns: (ns * 10.0).round() / 10.0,
                pinocchio_ns: None,
                cppadcg_ns: None,
                code_kb: None,
                l1i_kib: None,
            });
        }
    }
    rows.sort_by(|a, b| {
        (&a.robot, &a.function, &a.frame, a.form).cmp(&(&b.robot, &b.function, &b.frame, b.form))
    });
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms_of_criterion_ids() {
        assert_eq!(form("generated"), Some(Form::Value));
        assert_eq!(form("generated_into"), Some(Form::Into));
        assert_eq!(form("generated_lanes8"), Some(Form::Lanes(8)));
        assert_eq!(form("generic"), None);
    }
}
