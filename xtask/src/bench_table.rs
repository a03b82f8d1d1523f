//! `cargo xtask bench-table`: the medians of the last `cargo bench --bench dynamics` run as a
//! Markdown table, generated beside generic, with their ratio.

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

/// Rows `robot → quantity → (generated, generic)` from `target/criterion`.
pub fn table(criterion: &Path) -> Result<String, String> {
    let mut rows: BTreeMap<(String, String), (Option<f64>, Option<f64>)> = BTreeMap::new();
    // Criterion names a group "robot/quantity" directory "robot_quantity"; robot names have
    // underscores too (panda_rounded), so the split comes from the group id it records.
    let entries = std::fs::read_dir(criterion).map_err(|e| {
        format!(
            "{}: {e} (run `cargo bench --bench dynamics` first)",
            criterion.display()
        )
    })?;
    for entry in entries.flatten() {
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
