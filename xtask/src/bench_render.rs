//! `cargo xtask bench-render`: the tables of BENCHMARKS.md, rendered from the latest rows of
//! `benchmarks/results.csv` ([`crate::results`]).
//!
//! A table stands between two marker lines, `<!-- rendered: MACHINE -->` and `<!-- /rendered -->`,
//! and shows that machine kind's rows; everything outside the markers is written by hand. A table
//! has a row per robot, function and frame (robots, then functions, in the order they first
//! appear in the results file), and a column per quantity that some row of it has: the anchors'
//! medians and dyngen's native median, dyngen written into a kept buffer (`_into`), per state in
//! lanes, the default build over the native one, the native machine code. Ratios are computed
//! here, each from the medians of one row of the file (one run), never typed.
//!
//! Some rows have a table of their own, a section of the machine's rows (`<!-- rendered:
//! MACHINE / contacts -->`, `… / free-flyer`): a row per function, the robots side by side. A
//! marker without a section shows the machine's other rows (those of a section the document
//! has no table for included).

use crate::results::{latest, Build, Form, Row};
use std::collections::{BTreeSet, HashMap};

const START: &str = "<!-- rendered: ";
const END: &str = "<!-- /rendered -->";
/// A value that was not measured.
const MISSING: &str = "—";
/// Between a marker's machine and its section.
const SECTION: &str = " / ";

/// Rows with a table of their own (`<!-- rendered: MACHINE / NAME -->`), a row per function with
/// the robots side by side, where a document has one for the machine.
struct Section {
    name: &'static str,
    /// The robots whose rows it holds; all robots if `None`.
    robots: Option<&'static [&'static str]>,
    /// Its functions, in table order.
    functions: &'static [&'static str],
}

impl Section {
    fn holds(&self, row: &Row) -> bool {
        self.functions.contains(&row.function.as_str())
            && self
                .robots
                .is_none_or(|robots| robots.contains(&row.robot.as_str()))
    }
}

const SECTIONS: &[Section] = &[
    // Constrained dynamics (`tools/compare_contacts.py`).
    Section {
        name: "contacts",
        robots: None,
        functions: &[
            "constrained_forward_dynamics",
            "constrained_forward_dynamics_baumgarte",
            "constrained_forward_dynamics_proximal",
            "impulse_dynamics",
            "operational_space_inertia",
            "contact_jacobian",
            "contact_drift",
            "contact_response",
            "constrained_forward_dynamics_derivatives",
        ],
    },
    // Free-flyer robots against both anchors (`tools/compare_floating.py`).
    Section {
        name: "free-flyer",
        robots: Some(&["solo12", "g1"]),
        functions: &[
            "mass_matrix",
            "coriolis",
            "gravity",
            "rnea",
            "aba",
            "minv",
            "rnea_derivatives",
            "aba_derivatives",
            "ccrba",
        ],
    },
];

/// The table between one pair of markers: the machine's rows outside the sections the document
/// gives it (`sections`), or one section's.
fn render_marked(rows: &[Row], marker: &str, sections: &[String]) -> Result<String, String> {
    let Some((machine, name)) = marker.rsplit_once(SECTION) else {
        let own = |r: &&Row| !(SECTIONS.iter()).any(|s| sections.iter().any(|n| n == s.name) && s.holds(r));
        let outside: Vec<Row> = rows.iter().filter(own).cloned().collect();
        return render_table(&outside, marker);
    };
    let Some(section) = SECTIONS.iter().find(|s| s.name == name) else {
        let known: Vec<&str> = SECTIONS.iter().map(|s| s.name).collect();
        return Err(format!("no section `{name}` (known: {})", known.join(", ")));
    };
    render_side_by_side(rows, machine, section)
}

/// The machine of each start marker in `document` (`MACHINE` or `MACHINE / SECTION`), trimmed.
fn markers(document: &str) -> Vec<&str> {
    document
        .lines()
        .filter_map(|l| l.trim().strip_prefix(START)?.strip_suffix(" -->"))
        .map(str::trim)
        .collect()
}

/// `document` with the table between each pair of markers rendered anew from `rows`.
pub fn render_document(document: &str, rows: &[Row]) -> Result<String, String> {
    let mut out = String::with_capacity(document.len());
    let mut lines = document.split_inclusive('\n').enumerate();
    while let Some((number, line)) = lines.next() {
        out.push_str(line);
        let Some(machine) = line
            .trim()
            .strip_prefix(START)
            .and_then(|l| l.strip_suffix(" -->"))
        else {
            if line.trim() == END {
                return Err(format!("line {}: `{END}` without a start marker", number + 1));
            }
            continue;
        };
        let machine = machine.trim();
        // The sections this machine has a table of its own for.
        let sections: Vec<String> = (markers(document).into_iter())
            .filter_map(|m| m.rsplit_once(SECTION))
            .filter(|(m, _)| *m == machine)
            .map(|(_, name)| name.to_owned())
            .collect();
        let table =
            render_marked(rows, machine, &sections).map_err(|e| format!("line {}: {e}", number + 1))?;
        if !line.ends_with('\n') {
            out.push('\n');
        }
        out.push_str(&table);
        loop {
            match lines.next() {
                Some((_, l)) if l.trim() == END => {
                    out.push_str(l);
                    break;
                }
                Some((n, l)) if l.trim().starts_with(START) => {
                    return Err(format!("line {}: a start marker before `{END}`", n + 1));
                }
                Some(_) => {}
                None => return Err(format!("line {}: no `{END}` after it", number + 1)),
            }
        }
    }
    Ok(out)
}

/// One row of a rendered table: the measurements of one robot's function (at one frame).
#[derive(Default)]
struct Entry<'a> {
    by_value: [Option<&'a Row>; 2],
    into: [Option<&'a Row>; 2],
    lanes: Vec<(u32, &'a Row)>,
}

fn slot(build: Build) -> usize {
    match build {
        Build::Native => 0,
        Build::Default => 1,
    }
}

/// Nanoseconds as the tables show them: whole above 10 ns.
fn ns(x: f64) -> String {
    if x >= 10.0 {
        format!("{x:.0}")
    } else {
        format!("{x:.1}")
    }
}

/// A ratio `a / b` with three significant figures at most.
fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(a), Some(b)) => {
            let r = a / b;
            if r >= 10.0 {
                format!("{r:.1}×")
            } else {
                format!("{r:.2}×")
            }
        }
        _ => MISSING.to_owned(),
    }
}

fn value(x: Option<f64>) -> String {
    x.map_or(MISSING.to_owned(), ns)
}

/// The Markdown table of one machine kind, with the dates of the runs it shows above it.
pub fn render_table(rows: &[Row], machine: &str) -> Result<String, String> {
    let shown = latest(rows, machine);
    if shown.is_empty() {
        return Err(format!("no results for the machine `{machine}`"));
    }
    // Robots, then their functions, in the order they first appear in the file.
    let mut robots: Vec<&str> = Vec::new();
    let mut entries: Vec<((&str, &str, &str), Entry)> = Vec::new();
    for row in rows.iter().filter(|r| r.machine == machine) {
        if !robots.contains(&row.robot.as_str()) {
            robots.push(&row.robot);
        }
        let key = (row.robot.as_str(), row.function.as_str(), row.frame.as_str());
        if !entries.iter().any(|(k, _)| *k == key) {
            entries.push((key, Entry::default()));
        }
    }
    let index: HashMap<_, _> = entries.iter().enumerate().map(|(i, (k, _))| (*k, i)).collect();
    let mut widths = BTreeSet::new();
    for row in &shown {
        let entry = &mut entries[index[&(row.robot.as_str(), row.function.as_str(), row.frame.as_str())]].1;
        match row.form {
            Form::Value => entry.by_value[slot(row.build)] = Some(row),
            Form::Into => entry.into[slot(row.build)] = Some(row),
            Form::Lanes(n) if row.build == Build::Native => {
                widths.insert(n);
                entry.lanes.push((n, row));
            }
            Form::Lanes(_) => {}
        }
    }
    entries.sort_by_key(|((robot, _, _), _)| robots.iter().position(|r| r == robot));

    let mut header = vec![
        "robot".to_owned(),
        "function".to_owned(),
        "Pinocchio".to_owned(),
        "CppADCodeGen".to_owned(),
        "dyngen".to_owned(),
        "Pinocchio / dyngen".to_owned(),
        "CppADCodeGen / dyngen".to_owned(),
        "`_into`".to_owned(),
        "Pinocchio / `_into`".to_owned(),
        "CppADCodeGen / `_into`".to_owned(),
    ];
    header.extend(widths.iter().map(|n| format!("{n} lanes, per state")));
    header.extend(["default / native".to_owned(), "code (KB)".to_owned()]);
    let mut body: Vec<Vec<String>> = Vec::new();
    for ((robot, function, frame), e) in &entries {
        let [native, default] = e.by_value;
        // The anchors as measured beside the native build, else beside the default one.
        let anchors = native.or(default);
        let into = e.into[0];
        let mut cells = vec![
            robot.to_string(),
            if frame.is_empty() {
                format!("`{function}`")
            } else {
                format!("`{function}` at `{frame}`")
            },
            value(anchors.and_then(|r| r.pinocchio_ns)),
            value(anchors.and_then(|r| r.cppadcg_ns)),
            value(native.map(|r| r.dyngen_ns)),
            ratio(native.and_then(|r| r.pinocchio_ns), native.map(|r| r.dyngen_ns)),
            ratio(native.and_then(|r| r.cppadcg_ns), native.map(|r| r.dyngen_ns)),
            value(into.map(|r| r.dyngen_ns)),
            ratio(into.and_then(|r| r.pinocchio_ns), into.map(|r| r.dyngen_ns)),
            ratio(into.and_then(|r| r.cppadcg_ns), into.map(|r| r.dyngen_ns)),
        ];
        for n in &widths {
            let per_state = e
                .lanes
                .iter()
                .find(|(w, _)| w == n)
                .map(|(w, r)| r.dyngen_ns / f64::from(*w));
            cells.push(value(per_state));
        }
        cells.push(ratio(default.map(|r| r.dyngen_ns), native.map(|r| r.dyngen_ns)));
        cells.push(match native.and_then(|r| r.code_kb.map(|kb| (kb, r.l1i_kib))) {
            None => MISSING.to_owned(),
            Some((kb, l1i)) if l1i.is_some_and(|l1i| kb * 1000.0 > l1i * 1024.0) => {
                format!("{kb:.1} (over L1i)")
            }
            Some((kb, _)) => format!("{kb:.1}"),
        });
        body.push(cells);
    }
    // Only the columns some row has.
    let keep: Vec<bool> = (0..header.len())
        .map(|c| c < 2 || body.iter().any(|cells| cells[c] != MISSING))
        .collect();
    let pick = |cells: &[String]| -> Vec<String> {
        cells
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(c, _)| c.clone())
            .collect()
    };

    let body: Vec<Vec<String>> = body.iter().map(|cells| pick(cells)).collect();
    Ok(measured_on(&shown) + &markdown(&pick(&header), 2, &body))
}

/// `Measured on DATE.` and a blank line; with runs of several dates, the robots of each.
fn measured_on(shown: &[&Row]) -> String {
    let mut dates: Vec<(&str, Vec<&str>)> = Vec::new();
    for row in shown {
        match dates.iter_mut().find(|(d, _)| *d == row.date) {
            Some((_, robots)) if robots.contains(&row.robot.as_str()) => {}
            Some((_, robots)) => robots.push(&row.robot),
            None => dates.push((&row.date, vec![&row.robot])),
        }
    }
    dates.sort();
    let mut out = String::from("Measured on ");
    if let [(date, _)] = dates.as_slice() {
        out.push_str(date);
    } else {
        let parts: Vec<String> = dates
            .iter()
            .map(|(date, robots)| format!("{date} ({})", robots.join(", ")))
            .collect();
        out.push_str(&parts.join(", "));
    }
    out.push_str(".\n\n");
    out
}

/// A Markdown table, its first `left` columns aligned left and the others (numbers) right.
fn markdown(header: &[String], left: usize, body: &[Vec<String>]) -> String {
    let mut out = format!("| {} |\n", header.join(" | "));
    out += &format!(
        "|{}\n",
        (0..header.len())
            .map(|c| if c < left { "---|" } else { "---:|" })
            .collect::<String>()
    );
    for cells in body {
        out += &format!("| {} |\n", cells.join(" | "));
    }
    out
}

/// A section's table: a row per function (in the section's order), and per robot (in the order
/// they first appear) Pinocchio's median, CppADCodeGen's where the robot has one, dyngen's (the
/// native build, else the default one) and the ratios. Before the section's first run: a line
/// that says so.
fn render_side_by_side(rows: &[Row], machine: &str, section: &Section) -> Result<String, String> {
    let all = latest(rows, machine);
    if all.is_empty() {
        return Err(format!("no results for the machine `{machine}`"));
    }
    let shown: Vec<&Row> = all
        .into_iter()
        .filter(|r| r.form == Form::Value && section.holds(r))
        .collect();
    if shown.is_empty() {
        return Ok("No run recorded yet.\n".to_owned());
    }
    let mut robots: Vec<(&str, bool)> = Vec::new();
    for row in &shown {
        if !robots.iter().any(|(r, _)| *r == row.robot) {
            let with_cg = shown
                .iter()
                .any(|r| r.robot == row.robot && r.cppadcg_ns.is_some());
            robots.push((&row.robot, with_cg));
        }
    }
    let find = |robot: &str, function: &str, build: Build| {
        shown
            .iter()
            .find(|r| r.robot == robot && r.function == function && r.build == build)
            .copied()
    };
    let mut header = vec!["function".to_owned()];
    for &(robot, with_cg) in &robots {
        header.push(format!("{robot}: Pinocchio"));
        if with_cg {
            header.push(format!("{robot}: CppADCodeGen"));
        }
        header.extend([format!("{robot}: dyngen"), format!("{robot}: Pinocchio / dyngen")]);
        if with_cg {
            header.push(format!("{robot}: CppADCodeGen / dyngen"));
        }
    }
    let mut body = Vec::new();
    for function in (section.functions.iter()).filter(|f| shown.iter().any(|r| r.function == **f)) {
        let mut cells = vec![format!("`{function}`")];
        for &(robot, with_cg) in &robots {
            let row = find(robot, function, Build::Native).or_else(|| find(robot, function, Build::Default));
            let dyngen = row.map(|r| r.dyngen_ns);
            cells.push(value(row.and_then(|r| r.pinocchio_ns)));
            if with_cg {
                cells.push(value(row.and_then(|r| r.cppadcg_ns)));
            }
            cells.extend([value(dyngen), ratio(row.and_then(|r| r.pinocchio_ns), dyngen)]);
            if with_cg {
                cells.push(ratio(row.and_then(|r| r.cppadcg_ns), dyngen));
            }
        }
        body.push(cells);
    }
    Ok(measured_on(&shown) + &markdown(&header, 1, &body))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::parse;

    const HEADER: &str =
        "machine,date,build,robot,function,frame,form,dyngen_ns,pinocchio_ns,cppadcg_ns,code_kb,l1i_kib\n";

    fn sample() -> Vec<Row> {
        parse(&format!(
            "{HEADER}\
M,2026-01-01,native,arm,fk,,value,40,400,100,0.5,32
M,2026-01-01,default,arm,fk,,value,44,400,100,,32
M,2026-01-01,native,arm,mass_matrix,,value,50,500,,40,32
M,2026-01-01,native,arm,mass_matrix,,into,40,500,,,32
M,2026-01-01,native,arm,rnea,,lanes4,80,,,,32
M,2026-01-02,native,arm,fk,,value,20,400,100,0.5,32
O,2026-01-03,native,arm,fk,,value,10,,,,
"
        ))
        .unwrap()
    }

    #[test]
    fn renders_ratios_missing_values_and_the_latest_run() {
        let table = render_table(&sample(), "M").unwrap();
        let lines: Vec<&str> = table.lines().collect();
        // Two runs of machine M: each robot listed under the dates of the rows shown.
        assert_eq!(lines[0], "Measured on 2026-01-01 (arm), 2026-01-02 (arm).");
        assert_eq!(
            lines[2],
            "| robot | function | Pinocchio | CppADCodeGen | dyngen | Pinocchio / dyngen | CppADCodeGen / dyngen \
             | `_into` | Pinocchio / `_into` | 4 lanes, per state | default / native | code (KB) |"
        );
        // fk: the 2026-01-02 native row (20 ns) replaces the 2026-01-01 one; 400 / 20 = 20.0×,
        // 100 / 20 = 5.00×; the default row (44 ns) against it, 2.20×.
        assert_eq!(
            lines[4],
            "| arm | `fk` | 400 | 100 | 20 | 20.0× | 5.00× | — | — | — | 2.20× | 0.5 |"
        );
        // No CppADCodeGen time: "—"; 40 KB of code is over a 32 KiB level-1 instruction cache.
        assert_eq!(
            lines[5],
            "| arm | `mass_matrix` | 500 | — | 50 | 10.0× | — | 40 | 12.5× | — | — | 40.0 (over L1i) |"
        );
        // Four states per call in 80 ns: 20 ns per state.
        assert_eq!(
            lines[6],
            "| arm | `rnea` | — | — | — | — | — | — | — | 20 | — | — |"
        );
        assert_eq!(
            render_table(&sample(), "O").unwrap().lines().next(),
            Some("Measured on 2026-01-03.")
        );
        assert!(render_table(&sample(), "P").is_err());
    }

    #[test]
    fn replaces_only_between_the_markers() {
        let doc = "# Title\n\nProse.\n<!-- rendered: O -->\nstale\n<!-- /rendered -->\nMore prose.\n";
        let out = render_document(doc, &sample()).unwrap();
        assert_eq!(
            out,
            "# Title\n\nProse.\n<!-- rendered: O -->\nMeasured on 2026-01-03.\n\n\
             | robot | function | dyngen |\n|---|---|---:|\n| arm | `fk` | 10 |\n<!-- /rendered -->\nMore prose.\n"
        );
        assert_eq!(render_document(&out, &sample()).unwrap(), out);
        assert!(render_document("<!-- rendered: O -->\n", &sample()).is_err());
        assert!(render_document("<!-- /rendered -->\n", &sample()).is_err());
    }

    #[test]
    fn frames_name_their_frame() {
        let rows = parse(&format!(
            "{HEADER}F,2026-01-01,native,arm,frame_pose,link4,value,25,250,,,\n"
        ))
        .unwrap();
        let table = render_table(&rows, "F").unwrap();
        assert!(
            table.contains("| arm | `frame_pose` at `link4` | 250 | 25 | 10.0× |"),
            "{table}"
        );
    }

    #[test]
    fn a_section_has_its_own_table_with_the_robots_side_by_side() {
        let rows = parse(&format!(
            "{HEADER}\
C,2026-01-01,native,quad,fk,,value,50,500,,,
C,2026-01-01,native,quad,impulse_dynamics,,value,400,4000,,,
C,2026-01-01,native,quad,constrained_forward_dynamics,,value,500,6000,,,
C,2026-01-01,native,biped,constrained_forward_dynamics,,value,2000,8000,,,
"
        ))
        .unwrap();
        let doc =
            "<!-- rendered: C -->\n<!-- /rendered -->\n<!-- rendered: C / contacts -->\n<!-- /rendered -->\n";
        let out = render_document(doc, &rows).unwrap();
        // The machine's own table leaves the section's functions out …
        assert!(out.contains("| quad | `fk` | 500 | 50 | 10.0× |"), "{out}");
        assert!(!out.contains("| quad | `impulse_dynamics`"), "{out}");
        // … which have a row each, in the section's order, the robots side by side; a robot
        // without the function has "—".
        assert!(
            out.contains(
                "| function | quad: Pinocchio | quad: dyngen | quad: Pinocchio / dyngen \
                 | biped: Pinocchio | biped: dyngen | biped: Pinocchio / dyngen |\n|---|---:|---:|---:|---:|---:|---:|\n\
                 | `constrained_forward_dynamics` | 6000 | 500 | 12.0× | 8000 | 2000 | 4.00× |\n\
                 | `impulse_dynamics` | 4000 | 400 | 10.0× | — | — | — |\n<!-- /rendered -->"
            ),
            "{out}"
        );
        // Before a section's first run, a line says so; an unknown section or machine is an error.
        let fk_only = parse(&format!("{HEADER}C,2026-01-01,native,quad,fk,,value,50,500,,,\n")).unwrap();
        let empty =
            render_document("<!-- rendered: C / contacts -->\n<!-- /rendered -->\n", &fk_only).unwrap();
        assert!(
            empty.contains("No run recorded yet.\n<!-- /rendered -->"),
            "{empty}"
        );
        assert!(render_document("<!-- rendered: C / nothing -->\n<!-- /rendered -->\n", &rows).is_err());
        assert!(render_document("<!-- rendered: D / contacts -->\n<!-- /rendered -->\n", &rows).is_err());
    }

    #[test]
    fn a_free_flyer_section_shows_both_anchors_where_the_document_has_one() {
        let rows = parse(&format!(
            "{HEADER}\
F,2026-01-01,native,g1,mass_matrix,,value,800,2400,1400,,
F,2026-01-01,native,g1,mass_matrix,,into,700,2400,1400,,
F,2026-01-01,native,panda,mass_matrix,,value,50,500,100,,
"
        ))
        .unwrap();
        let both = "<!-- rendered: F -->\n<!-- /rendered -->\n<!-- rendered: F / free-flyer -->\n<!-- /rendered -->\n";
        let out = render_document(both, &rows).unwrap();
        // The arm stays in the machine's table; the G1 has the section's, both anchors beside it.
        assert!(
            out.contains("| panda | `mass_matrix` | 500 | 100 | 50 | 10.0× | 2.00× |"),
            "{out}"
        );
        assert!(!out.contains("| g1 | `mass_matrix`"), "{out}");
        assert!(
            out.contains(
                "| function | g1: Pinocchio | g1: CppADCodeGen | g1: dyngen | g1: Pinocchio / dyngen \
                 | g1: CppADCodeGen / dyngen |\n|---|---:|---:|---:|---:|---:|\n\
                 | `mass_matrix` | 2400 | 1400 | 800 | 3.00× | 1.75× |\n<!-- /rendered -->"
            ),
            "{out}"
        );
        // Without the section's table, the G1's rows stay in the machine's.
        let own = render_document("<!-- rendered: F -->\n<!-- /rendered -->\n", &rows).unwrap();
        assert!(
            own.contains("| g1 | `mass_matrix` | 2400 | 1400 | 800 | 3.00× | 1.75× | 700 |"),
            "{own}"
        );
    }

    /// BENCHMARKS.md's tables are what the committed results render to.
    #[test]
    fn benchmarks_md_is_rendered_from_the_committed_results() {
        let root = crate::workspace_root();
        let rows = crate::results::read(&root.join(crate::RESULTS)).unwrap();
        let document = std::fs::read_to_string(root.join(crate::BENCHMARKS)).unwrap();
        let rendered = render_document(&document, &rows).unwrap();
        assert!(
            rendered == document,
            "{} is not what {} renders to: run `cargo xtask bench-render` and commit the result",
            crate::BENCHMARKS,
            crate::RESULTS
        );
    }
}
