//! The loader fuzzer: mutated robot descriptions into the public loaders, on stable Rust.
//!
//! One case = one 64-bit seed: pick a valid description (the committed robots and two small
//! ones), apply one to three mutations (byte-level: random bytes, truncation, flips, splices
//! of two files; structure-aware: delete, duplicate or swap YAML blocks and XML elements,
//! numbers replaced by NaN/inf/huge/negative/empty values, names replaced, deep nesting, very
//! long tokens), and load the text with `load_yaml_str` or `load_urdf_str` inside
//! `catch_unwind`. The case passes when the loader returns either a model that validates and
//! has only finite numbers, or an error whose message names the file and says something.
//! A small share of the accepted models also goes through the generator (trace + emit).
//!
//! Used by `codegen/tests/suite/fuzz.rs` (a fast fixed-seed slice) and `cargo xtask fuzz` (the long run,
//! the same code in release). A case is replayed from its seed alone.

use crate::random_model::SplitMix64;
use dyngen_codegen::description::{load_urdf_str, load_yaml_str, Choices, Loaded};
use dyngen_codegen::internals::generate::{emit, trace, Provenance};
use dyngen_codegen::model::Model;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Inputs longer than this are cut (keeps each case fast; deep nesting fits well inside).
pub const MAX_INPUT: usize = 1 << 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Yaml,
    Urdf,
}

/// A valid description to mutate.
#[derive(Clone, Debug)]
pub struct SeedFile {
    pub text: String,
    pub format: Format,
    /// The name given to the loader (a real path for the committed robots, so `urdf:` resolves).
    pub file: PathBuf,
}

const SMALL_YAML: &str = "\
name: small
gravity: [0.0, 0.0, -9.81]
end_effector: { name: tool, link: l2, xyz: [0.0, 0.0, 0.1], rpy: [0.0, 0.0, 0.0] }
locked_joints: { j3: 0.0 }
links:
  - name: base
  - name: l1
    inertial:
      mass: 1.0
      origin: { xyz: [0.0, 0.0, 0.1], rpy: [0.0, 0.0, 0.0] }
      inertia: { ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }
  - name: l2
    inertial:
      mass: 0.5
      inertia: { ixx: 0.01, ixy: 0.0, ixz: 0.0, iyy: 0.01, iyz: 0.0, izz: 0.01 }
  - name: l3
    inertial:
      mass: 0.2
      inertia: { ixx: 0.001, ixy: 0.0, ixz: 0.0, iyy: 0.001, iyz: 0.0, izz: 0.001 }
joints:
  - name: j1
    type: revolute
    parent: base
    child: l1
    origin: { xyz: [0.0, 0.0, 0.2], rpy: [0.0, 0.0, 0.0] }
    axis: [0, 0, 1]
    limit: { lower: -1.0, upper: 1.0, velocity: 1.0, effort: 10.0 }
  - name: j2
    type: prismatic
    parent: l1
    child: l2
    axis: [1, 0, 0]
    limit: { lower: 0.0, upper: 0.5, velocity: 1.0, effort: 10.0 }
  - name: j3
    type: continuous
    parent: l1
    child: l3
    origin: { xyz: [0.1, 0.0, 0.0], rpy: [1.5707963267948966, 0.0, 0.0] }
    axis: [0, 1, 0]
";

const SMALL_URDF: &str = r#"<?xml version="1.0"?>
<robot name="small">
  <link name="base"/>
  <link name="l1">
    <inertial>
      <origin xyz="0 0 0.1" rpy="0 0 0"/>
      <mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
  </link>
  <link name="l2">
    <inertial><mass value="0.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <link name="tool"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.2" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <joint name="j2" type="continuous">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0.1 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 1 0"/>
  </joint>
  <joint name="fix" type="fixed">
    <parent link="l2"/><child link="tool"/><origin xyz="0 0 0.05"/>
  </joint>
</robot>
"#;

/// The committed robots plus two small descriptions that use every feature.
pub fn corpus(root: &Path) -> Vec<SeedFile> {
    let mut seeds = Vec::new();
    for (dir, format) in [("robots", Format::Yaml), ("robots/urdf", Format::Urdf)] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root.join(dir))
            .expect("robots directory")
            .map(|e| e.expect("entry").path())
            .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "urdf")))
            .collect();
        files.sort();
        for file in files {
            let text = std::fs::read_to_string(&file).expect("readable robot");
            seeds.push(SeedFile { text, format, file });
        }
    }
    let small_yaml = SeedFile {
        text: SMALL_YAML.into(),
        format: Format::Yaml,
        file: root.join("robots/fuzz_small.yaml"),
    };
    let small_urdf = SeedFile {
        text: SMALL_URDF.into(),
        format: Format::Urdf,
        file: root.join("robots/urdf/fuzz_small.urdf"),
    };
    // The small files are cheap and dense in features: give them most of the cases, however
    // many robots the repository has.
    for _ in 0..seeds.len().div_ceil(2).max(3) {
        seeds.push(small_yaml.clone());
        seeds.push(small_urdf.clone());
    }
    seeds
}

/// Values that replace a number.
const BAD_NUMBERS: &[&str] = &[
    "NaN",
    "nan",
    ".nan",
    ".NaN",
    "inf",
    "-inf",
    ".inf",
    "-.inf",
    "infinity",
    "1e308",
    "-1e308",
    "1e309",
    "-1",
    "-0.5",
    "",
    "0",
    "-0",
    "0.0",
    "1e-320",
    "5e-324",
    "1e-300",
    "1e300",
    "1e4",
    "1e5",
    "123456789",
    "0x10",
    "1,5",
    "1_000",
    "+",
    "-",
    ".",
    "e5",
    "~",
    "null",
    "true",
    "'1'",
    "\"\"",
];

/// Words that replace a name or keyword.
const WORDS: &[&str] = &[
    "floating",
    "planar",
    "fixed",
    "continuous",
    "prismatic",
    "revolute",
    "spherical",
    "",
    "base",
    "l1",
    "null",
    "~",
    "[]",
    "{}",
    "&a",
    "*a",
    "!!binary",
    "xacro:include",
    "robot",
    "link",
    "joint",
];

fn pick<'a, T>(rng: &mut SplitMix64, items: &'a [T]) -> &'a T {
    &items[(rng.next_u64() % items.len() as u64) as usize]
}

fn below(rng: &mut SplitMix64, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (rng.next_u64() % n as u64) as usize
    }
}

/// Roughly log-uniform in `1..=max`: small sizes often, huge ones sometimes.
fn log_size(rng: &mut SplitMix64, max: usize) -> usize {
    let bits = below(rng, (usize::BITS - max.leading_zeros()) as usize + 1);
    (1 + below(rng, 1usize << bits)).min(max)
}

fn floor_char(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Token spans in `text` that `is_token` accepts char by char, with `is_start` for the first.
fn tokens(text: &str, is_start: fn(char) -> bool, is_token: fn(char) -> bool) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices().chain(std::iter::once((text.len(), ' '))) {
        match start {
            None if is_start(c) => start = Some(i),
            Some(s) if !is_token(c) => {
                spans.push((s, i));
                start = if is_start(c) { Some(i) } else { None };
            }
            _ => {}
        }
    }
    spans
}

fn numbers(text: &str) -> Vec<(usize, usize)> {
    let mut spans = tokens(
        text,
        |c| c.is_ascii_digit() || c == '-' || c == '.',
        |c| c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '+'),
    );
    spans.retain(|&(a, b)| text[a..b].bytes().any(|c| c.is_ascii_digit()));
    spans
}

fn words(text: &str) -> Vec<(usize, usize)> {
    tokens(
        text,
        |c| c.is_ascii_alphabetic() || c == '_',
        |c| c.is_ascii_alphanumeric() || c == '_',
    )
}

fn replace(text: &str, (a, b): (usize, usize), with: &str) -> String {
    format!("{}{with}{}", &text[..a], &text[b..])
}

/// Line spans (with their newline).
fn lines(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for (i, c) in text.char_indices() {
        if c == '\n' {
            spans.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < text.len() {
        spans.push((start, text.len()));
    }
    spans
}

/// YAML blocks: a line and the more-indented lines after it (a list item with its fields).
fn yaml_blocks(text: &str) -> Vec<(usize, usize)> {
    let ls = lines(text);
    let indent = |(a, b): (usize, usize)| {
        let l = &text[a..b];
        let t = l.trim_start_matches([' ', '-']);
        (l.len() - t.len(), t.trim().is_empty())
    };
    (0..ls.len())
        .map(|i| {
            let (own, _) = indent(ls[i]);
            let mut end = i + 1;
            while end < ls.len() {
                let (ind, blank) = indent(ls[end]);
                if !blank && ind <= own {
                    break;
                }
                end += 1;
            }
            (ls[i].0, ls[end - 1].1)
        })
        .collect()
}

/// XML elements (start of the start tag to the end of the end tag); lines if not XML.
fn xml_elements(text: &str) -> Vec<(usize, usize)> {
    match roxmltree::Document::parse(text) {
        Ok(doc) => doc
            .descendants()
            .filter(|n| n.is_element())
            .map(|n| (n.range().start, n.range().end))
            .collect(),
        Err(_) => lines(text),
    }
}

fn delete(text: &str, span: (usize, usize)) -> String {
    replace(text, span, "")
}

fn duplicate(text: &str, (a, b): (usize, usize)) -> String {
    format!("{}{}", &text[..b], &text[a..])
}

/// Swaps two spans that do not overlap; `None` if they do.
fn swap(text: &str, x: (usize, usize), y: (usize, usize)) -> Option<String> {
    let (p, q) = if x.0 <= y.0 { (x, y) } else { (y, x) };
    (p.1 <= q.0).then(|| {
        format!(
            "{}{}{}{}{}",
            &text[..p.0],
            &text[q.0..q.1],
            &text[p.1..q.0],
            &text[p.0..p.1],
            &text[q.1..]
        )
    })
}

/// The mutators, by name (the name is reported with a finding).
pub const MUTATORS: &[&str] = &[
    "random-bytes",
    "truncate",
    "flip-bytes",
    "splice",
    "insert-bytes",
    "delete-block",
    "duplicate-block",
    "swap-blocks",
    "delete-line",
    "duplicate-line",
    "swap-lines",
    "bad-number",
    "bad-number-all",
    "replace-word",
    "delete-word",
    "deep-nesting",
    "long-token",
];

/// Applies mutator `which` to `text`.
pub fn mutate(which: usize, text: &str, format: Format, corpus: &[SeedFile], rng: &mut SplitMix64) -> String {
    let blocks = |t: &str| match format {
        Format::Yaml => yaml_blocks(t),
        Format::Urdf => xml_elements(t),
    };
    match MUTATORS[which] {
        "random-bytes" => {
            let n = log_size(rng, 4096);
            let bytes: Vec<u8> = (0..n)
                .map(|_| match below(rng, 4) {
                    // Mostly printable characters that matter to YAML and XML.
                    0 => *pick(rng, b"[]{}<>/:-,\"'&*!#|>=? \n\t0123456789.e"),
                    1 => b' ' + below(rng, 95) as u8,
                    _ => rng.next_u64() as u8,
                })
                .collect();
            String::from_utf8_lossy(&bytes).into_owned()
        }
        "truncate" => text[..floor_char(text, below(rng, text.len() + 1))].to_owned(),
        "flip-bytes" => {
            let mut bytes = text.as_bytes().to_vec();
            for _ in 0..1 + below(rng, 8) {
                if !bytes.is_empty() {
                    let i = below(rng, bytes.len());
                    bytes[i] = match below(rng, 3) {
                        0 => bytes[i] ^ (1 << below(rng, 8)),
                        1 => *pick(rng, b"[]{}<>/:-,\"'&*!# \n0.e"),
                        _ => rng.next_u64() as u8,
                    };
                }
            }
            String::from_utf8_lossy(&bytes).into_owned()
        }
        "splice" => {
            let other = &pick(rng, corpus).text;
            let a = floor_char(text, below(rng, text.len() + 1));
            let b = floor_char(other, below(rng, other.len() + 1));
            format!("{}{}", &text[..a], &other[b..])
        }
        "insert-bytes" => {
            let at = floor_char(text, below(rng, text.len() + 1));
            let junk: String = (0..1 + below(rng, 16))
                .map(|_| {
                    *pick(
                        rng,
                        &[
                            '[', ']', '{', '}', '<', '>', '/', ':', '-', '"', '\'', '&', '*', '\n', ' ',
                            '\t', '\0', 'é', '\u{FEFF}',
                        ],
                    )
                })
                .collect();
            format!("{}{junk}{}", &text[..at], &text[at..])
        }
        m @ ("delete-block" | "duplicate-block" | "swap-blocks" | "delete-line" | "duplicate-line"
        | "swap-lines") => {
            let spans = if m.ends_with("line") || m.ends_with("lines") {
                lines(text)
            } else {
                blocks(text)
            };
            if spans.is_empty() {
                return text.to_owned();
            }
            let x = *pick(rng, &spans);
            match m {
                "delete-block" | "delete-line" => delete(text, x),
                "duplicate-block" | "duplicate-line" => duplicate(text, x),
                _ => swap(text, x, *pick(rng, &spans)).unwrap_or_else(|| delete(text, x)),
            }
        }
        "bad-number" => {
            let spans = numbers(text);
            if spans.is_empty() {
                return text.to_owned();
            }
            let mut out = text.to_owned();
            // Several at once sometimes; from the back so earlier spans stay valid.
            let mut chosen: Vec<(usize, usize)> =
                (0..1 + below(rng, 3)).map(|_| *pick(rng, &spans)).collect();
            chosen.sort();
            chosen.dedup();
            for span in chosen.into_iter().rev() {
                let value = *pick::<&str>(rng, BAD_NUMBERS);
                out = replace(&out, span, value);
            }
            out
        }
        "bad-number-all" => {
            let value = *pick(rng, BAD_NUMBERS);
            let mut out = text.to_owned();
            for span in numbers(text).into_iter().rev() {
                if below(rng, 4) == 0 {
                    out = replace(&out, span, value);
                }
            }
            out
        }
        "replace-word" => {
            let spans = words(text);
            if spans.is_empty() {
                return text.to_owned();
            }
            let x = *pick(rng, &spans);
            let with = if below(rng, 2) == 0 {
                let y = *pick(rng, &spans);
                text[y.0..y.1].to_owned()
            } else {
                (*pick(rng, WORDS)).to_owned()
            };
            replace(text, x, &with)
        }
        "delete-word" => {
            let spans = words(text);
            if spans.is_empty() {
                return text.to_owned();
            }
            delete(text, *pick(rng, &spans))
        }
        "deep-nesting" => {
            let depth = log_size(rng, 200_000);
            let (open, close) = *pick(
                rng,
                &[
                    ("[", "]"),
                    ("{a: ", "}"),
                    ("- ", ""),
                    ("<a>", "</a>"),
                    ("<link name=\"x\">", "</link>"),
                    ("[", ""),
                    ("<a>", ""),
                ],
            );
            let at = floor_char(text, below(rng, text.len() + 1));
            format!(
                "{}{}{}{}",
                &text[..at],
                open.repeat(depth),
                close.repeat(depth),
                &text[at..]
            )
        }
        "long-token" => {
            let n = log_size(rng, 200_000);
            let token = pick(rng, &["a", "9", "-", " ", "é", "1e"]).repeat(n);
            let spans = if below(rng, 2) == 0 {
                numbers(text)
            } else {
                words(text)
            };
            match spans.is_empty() {
                true => format!("{text}{token}"),
                false => replace(text, *pick(rng, &spans), &token),
            }
        }
        other => unreachable!("mutator {other}"),
    }
}

/// What a case did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    pub cases: u64,
    pub accepted: u64,
    pub rejected: u64,
    pub generated: u64,
}

impl Tally {
    pub fn add(&mut self, other: &Tally) {
        self.cases += other.cases;
        self.accepted += other.accepted;
        self.rejected += other.rejected;
        self.generated += other.generated;
    }
}

/// A case that broke a rule: a panic, an accepted model that is invalid, a bad message.
#[derive(Clone, Debug)]
pub struct Finding {
    pub seed: u64,
    pub mutators: Vec<&'static str>,
    pub problem: String,
    pub input: String,
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic with a non-string payload".into())
}

/// Every number of a model is finite.
pub fn model_is_finite(m: &Model) -> bool {
    let pose_ok = |p: &dyngen_codegen::model::Pose| {
        p.rotation
            .iter()
            .chain(p.translation.iter())
            .all(|v| v.is_finite())
    };
    m.gravity().iter().all(|v| v.is_finite())
        && pose_ok(&m.end_effector().placement)
        && m.joints().iter().all(|j| {
            pose_ok(&j.origin)
                && j.axis.iter().all(|v| v.is_finite())
                && j.limits.iter().all(|l| {
                    [l.lower, l.upper, l.velocity, l.effort]
                        .iter()
                        .all(|v| v.is_finite())
                })
        })
        && m.bodies().iter().all(|b| {
            let i = &b.inertia;
            i.mass.is_finite()
                && i.com.iter().all(|v| v.is_finite())
                && i.inertia_com.iter().all(|v| v.is_finite())
        })
}

/// Loads `text` as `format`, named `file`, and checks the outcome. `Ok(Some(model))` when
/// accepted, `Ok(None)` when rejected properly, `Err(problem)` when a rule was broken.
pub fn check_input(text: &str, format: Format, file: &Path) -> Result<Option<Loaded>, String> {
    let result = catch_unwind(AssertUnwindSafe(|| match format {
        Format::Yaml => load_yaml_str(text, file),
        Format::Urdf => load_urdf_str(text, file, &Choices::default()),
    }));
    match result {
        Err(p) => Err(format!("the loader panicked: {}", panic_message(&*p))),
        Ok(Ok(loaded)) => {
            if !model_is_finite(&loaded.model) {
                return Err("accepted a model with a number that is not finite".into());
            }
            Ok(Some(loaded))
        }
        Ok(Err(e)) => {
            let shown = e.to_string();
            let named = e.file == file
                || e.file
                    .file_name()
                    .is_some_and(|n| text.contains(n.to_string_lossy().as_ref()));
            if e.message.contains("internal error") {
                // `Model::new` refused what the loader built: a loader bug.
                Err(format!(
                    "the loader built a model that breaks an invariant: {shown:?}"
                ))
            } else if e.message.trim().is_empty() {
                Err(format!("an error with an empty message: {shown:?}"))
            } else if !named || !shown.starts_with(&e.file.display().to_string()) {
                Err(format!("an error that does not name the file: {shown:?}"))
            } else {
                Ok(None)
            }
        }
    }
}

/// Traces and emits a model inside `catch_unwind`; the code must be non-empty.
pub fn check_generation(model: &Model) -> Result<(), String> {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let robot = trace(model);
        if robot.non_finite_constant().is_some() {
            // `generate_robot` refuses this model with an error; nothing to emit.
            return "impl (refused: overflow)".to_owned();
        }
        let provenance = Provenance {
            source: "fuzz".into(),
            source_hash: "0".into(),
            regenerate: "fuzz".into(),
            type_name: "Fuzz".into(),
        };
        emit(model, &robot, &provenance)
    }));
    match result {
        Ok(code) if code.contains("impl") => Ok(()),
        Ok(_) => Err("generation produced no implementation".into()),
        Err(p) => Err(format!("generation panicked: {}", panic_message(&*p))),
    }
}

/// Generate code for this share of accepted mutants (1 in `GENERATE_EVERY`) with at most
/// `GENERATE_MAX_DOF` joints, so that tracing does not dominate the run.
pub const GENERATE_EVERY: u64 = 8;
pub const GENERATE_MAX_DOF: usize = 3;

/// The input of case `seed`: text, loader, file name, mutators applied, and the generator
/// (to continue the case's random choices).
pub struct Input<'c> {
    pub text: String,
    pub format: Format,
    pub file: &'c Path,
    pub applied: Vec<&'static str>,
    rng: SplitMix64,
}

/// Builds the input of case `seed`.
pub fn make_input(corpus: &[SeedFile], seed: u64) -> Input<'_> {
    let mut rng = SplitMix64::new(seed);
    let base = pick(&mut rng, corpus);
    let mut text = base.text.clone();
    let mut applied = Vec::new();
    for _ in 0..1 + below(&mut rng, 3) {
        let which = below(&mut rng, MUTATORS.len());
        text = mutate(which, &text, base.format, corpus, &mut rng);
        applied.push(MUTATORS[which]);
        if text.len() > MAX_INPUT {
            text.truncate(floor_char(&text, MAX_INPUT));
        }
    }
    // Now and then, the wrong loader for the text.
    let format = match (below(&mut rng, 32), base.format) {
        (0, Format::Yaml) => Format::Urdf,
        (0, Format::Urdf) => Format::Yaml,
        (_, f) => f,
    };
    Input {
        text,
        format,
        file: &base.file,
        applied,
        rng,
    }
}

/// Runs the case of `seed`.
pub fn run_case(corpus: &[SeedFile], seed: u64) -> Result<Tally, Finding> {
    let Input {
        text,
        format,
        file,
        applied,
        mut rng,
    } = make_input(corpus, seed);
    let finding = |problem: String, text: &str| Finding {
        seed,
        mutators: applied.clone(),
        problem,
        input: text.to_owned(),
    };
    let mut tally = Tally {
        cases: 1,
        ..Tally::default()
    };
    match check_input(&text, format, file) {
        Err(problem) => return Err(finding(problem, &text)),
        Ok(None) => tally.rejected += 1,
        Ok(Some(loaded)) => {
            tally.accepted += 1;
            if loaded.model.dof() <= GENERATE_MAX_DOF && below(&mut rng, GENERATE_EVERY as usize) == 0 {
                check_generation(&loaded.model).map_err(|p| finding(p, &text))?;
                tally.generated += 1;
            }
        }
    }
    Ok(tally)
}

/// The seed of case `i` of a run with seed `run_seed`.
pub fn case_seed(run_seed: u64, i: u64) -> u64 {
    SplitMix64::new(run_seed ^ i.wrapping_mul(0xD1B5_4A32_D192_ED03)).next_u64()
}

/// Runs `cases` cases on `threads` worker threads (2 MiB stacks, like any spawned thread, so a
/// recursion that would overflow a build script's main thread overflows here first). A case
/// that runs longer than `hang_after` is reported and the process aborts with its seed.
pub fn run(
    corpus: &[SeedFile],
    run_seed: u64,
    cases: u64,
    threads: usize,
    hang_after: Duration,
    progress: Option<&dyn Fn(u64)>,
) -> (Tally, Vec<Finding>) {
    let next = Arc::new(AtomicU64::new(0));
    let done = Arc::new(AtomicU64::new(0));
    // Per thread: the case being run and when it started (ms since `epoch`), 0 when idle.
    let epoch = Instant::now();
    let busy: Arc<Vec<(AtomicU64, AtomicU64)>> = Arc::new(
        (0..threads)
            .map(|_| (AtomicU64::new(0), AtomicU64::new(0)))
            .collect(),
    );
    let finished = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let watchdog = {
        let (busy, finished) = (busy.clone(), finished.clone());
        std::thread::spawn(move || {
            while !finished.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(200));
                let now = epoch.elapsed().as_millis() as u64;
                for (case, since) in busy.iter() {
                    let started = since.load(Ordering::Relaxed);
                    if started != 0 && now.saturating_sub(started) > hang_after.as_millis() as u64 {
                        let i = case.load(Ordering::Relaxed);
                        eprintln!(
                            "fuzz: HANG: case {i} (case seed {:#018x}) ran longer than {hang_after:?}",
                            case_seed(run_seed, i)
                        );
                        std::process::abort();
                    }
                }
            }
        })
    };
    let results = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let (next, done, busy) = (&next, &done, &busy);
                std::thread::Builder::new()
                    .stack_size(2 << 20)
                    .spawn_scoped(scope, move || {
                        let mut tally = Tally::default();
                        let mut findings = Vec::new();
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            if i >= cases {
                                break;
                            }
                            busy[t].0.store(i, Ordering::Relaxed);
                            busy[t]
                                .1
                                .store(epoch.elapsed().as_millis() as u64 + 1, Ordering::Relaxed);
                            match run_case(corpus, case_seed(run_seed, i)) {
                                Ok(t) => tally.add(&t),
                                Err(f) => {
                                    tally.cases += 1;
                                    findings.push(f);
                                }
                            }
                            busy[t].1.store(0, Ordering::Relaxed);
                            done.fetch_add(1, Ordering::Relaxed);
                        }
                        (tally, findings)
                    })
                    .expect("spawn fuzz worker")
            })
            .collect();
        if let Some(report) = progress {
            let mut last = Instant::now();
            while handles.iter().any(|h| !h.is_finished()) {
                std::thread::sleep(Duration::from_millis(100));
                if last.elapsed() >= Duration::from_secs(10) {
                    last = Instant::now();
                    report(done.load(Ordering::Relaxed));
                }
            }
        }
        handles
            .into_iter()
            .map(|h| h.join().expect("fuzz worker"))
            .collect::<Vec<_>>()
    });
    finished.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    let mut tally = Tally::default();
    let mut findings = Vec::new();
    for (t, f) in results {
        tally.add(&t);
        findings.extend(f);
    }
    findings.sort_by_key(|f| f.seed);
    (tally, findings)
}

/// The first five findings, readable: case seed, mutators, problem, the start of the input.
pub fn report(findings: &[Finding]) -> String {
    findings
        .iter()
        .take(5)
        .map(|f| {
            let shown: String = f.input.chars().take(400).collect();
            format!(
                "case seed {:#018x} ({:?}): {}\ninput (first 400 chars):\n{shown}\n",
                f.seed, f.mutators, f.problem
            )
        })
        .collect()
}

/// The long run of `cargo xtask fuzz`: `cases` cases from run seed `seed` on `threads`
/// threads with progress on stderr, or only the case `replay` (a case seed, whose input is
/// written to `target/fuzz-case-<seed>.txt`). Findings are written to `target/fuzz-findings/`
/// and returned as the error.
pub fn long_run(cases: u64, seed: u64, threads: usize, replay: Option<u64>) -> Result<(), String> {
    let root = crate::workspace_root();
    let corpus = corpus(root);
    if let Some(s) = replay {
        let input = make_input(&corpus, s);
        let dump = root.join(format!("target/fuzz-case-{s:016x}.txt"));
        let _ = std::fs::write(&dump, &input.text);
        eprintln!(
            "replaying case seed {s:#018x}: {:?} as {:?} ({}), input in {}",
            input.applied,
            input.format,
            input.file.display(),
            dump.display()
        );
        return match run_case(&corpus, s) {
            Ok(t) => {
                eprintln!("ok: {t:?}");
                Ok(())
            }
            Err(f) => Err(report(&[f])),
        };
    }
    eprintln!("fuzz: {cases} cases, run seed {seed}, {threads} threads");
    let start = Instant::now();
    let progress = |done: u64| {
        let secs = start.elapsed().as_secs_f64();
        eprintln!(
            "fuzz: {done}/{cases} cases, {secs:.0} s, {:.0} cases/s",
            done as f64 / secs
        );
    };
    let (tally, findings) = run(
        &corpus,
        seed,
        cases,
        threads,
        Duration::from_secs(30),
        Some(&progress),
    );
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "fuzz: done: {} cases in {secs:.1} s ({:.0} cases/s): {} accepted, {} rejected, {} generated, {} findings",
        tally.cases,
        tally.cases as f64 / secs,
        tally.accepted,
        tally.rejected,
        tally.generated,
        findings.len()
    );
    if findings.is_empty() {
        return Ok(());
    }
    let dir = root.join("target/fuzz-findings");
    let _ = std::fs::create_dir_all(&dir);
    for f in &findings {
        let _ = std::fs::write(dir.join(format!("{:016x}.txt", f.seed)), &f.input);
    }
    Err(format!(
        "{} findings (inputs in {}):\n{}",
        findings.len(),
        dir.display(),
        report(&findings)
    ))
}
