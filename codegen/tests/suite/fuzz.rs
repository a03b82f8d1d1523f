//! Fuzzing the loaders on stable Rust: every input ends in a valid model or an error value,
//! never a panic, an abort, a hang or a stack overflow (harness: `dyngen_testkit::fuzz`; the
//! long run is `cargo xtask fuzz [--cases N] [--seed S]`).
//!
//! - `fuzz_fast_slice`: a fixed-seed slice of the mutation fuzzer in every `cargo test`.
//! - regression inputs and the stack-depth probes, data-driven.
//! - random valid trees written as YAML and URDF load back to the same model.

use dyngen_codegen::description::{load_urdf_str, load_yaml_str, Choices, FrameSpec};
use dyngen_codegen::model::Model;
use dyngen_testkit::fuzz::{self, check_generation, check_input, corpus, Format};
use dyngen_testkit::random_model::arb_model;
use dyngen_testkit::serialize::{to_urdf, to_yaml};
use dyngen_testkit::workspace_root;
use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRunner};
use std::path::Path;
use std::time::{Duration, Instant};

/// A few thousand mutants from a fixed seed: the same inputs in every run.
#[test]
fn fuzz_fast_slice() {
    let corpus = corpus(workspace_root());
    for seed in &corpus {
        let loaded = check_input(&seed.text, seed.format, &seed.file).expect("no panic");
        assert!(
            loaded.is_some(),
            "{}: the unmutated seed is rejected",
            seed.file.display()
        );
    }
    let cases = 5000;
    let (tally, findings) = fuzz::run(&corpus, 0x005E_ED0F_F022, cases, 2, Duration::from_secs(60), None);
    assert!(
        findings.is_empty(),
        "{} of {cases} cases broke a rule:\n{}",
        findings.len(),
        fuzz::report(&findings)
    );
    assert_eq!(tally.cases, cases);
    // The mutants must exercise both outcomes, or the slice tests little.
    assert!(tally.accepted >= cases / 20, "{tally:?}");
    assert!(tally.rejected >= cases / 2, "{tally:?}");
    assert!(tally.generated >= 5, "{tally:?}");
}

/// Runs `f` on a thread with a 2 MiB stack (what a spawned thread gets by default; a build
/// script's main thread has more), so a deep recursion fails here first.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .expect("spawn")
        .join()
        .expect("no panic")
}

/// Each input must be rejected with a message containing the text, or accepted.
enum Expect {
    Error(&'static str),
    Accepted,
}

fn check_case(name: &str, text: String, format: Format, expect: Expect) {
    let file = Path::new(match format {
        Format::Yaml => "probe.yaml",
        Format::Urdf => "probe.urdf",
    });
    let start = Instant::now();
    let outcome = check_input(&text, format, file).unwrap_or_else(|p| panic!("{name}: {p}"));
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{name}: took {:?}",
        start.elapsed()
    );
    match (expect, outcome) {
        (Expect::Accepted, Some(_)) => {}
        (Expect::Accepted, None) => {
            let e = match format {
                Format::Yaml => load_yaml_str(&text, file).map(|_| ()),
                Format::Urdf => load_urdf_str(&text, file, &Choices::default()).map(|_| ()),
            };
            panic!("{name}: rejected: {e:?}")
        }
        (Expect::Error(piece), None) => {
            let e = match format {
                Format::Yaml => load_yaml_str(&text, file).err(),
                Format::Urdf => load_urdf_str(&text, file, &Choices::default()).err(),
            };
            let msg = e.map(|e| e.to_string()).unwrap_or_default();
            assert!(msg.contains(piece), "{name}: message lacks {piece:?}: {msg}");
        }
        (Expect::Error(piece), Some(_)) => panic!("{name}: accepted, expected an error with {piece:?}"),
    }
}

/// A chain of `n` revolute joints as YAML.
fn yaml_chain(n: usize) -> String {
    let mut s = String::from("name: chain\nlinks:\n  - name: l0\n");
    for i in 1..=n {
        s += &format!(
            "  - name: l{i}\n    inertial:\n      mass: 1.0\n      \
             inertia: {{ ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }}\n"
        );
    }
    s += "joints:\n";
    for i in 1..=n {
        s += &format!(
            "  - {{ name: j{i}, type: continuous, parent: l{}, child: l{i}, axis: [0, 0, 1], \
             origin: {{ xyz: [0, 0, 0.1], rpy: [0, 0, 0] }} }}\n",
            i - 1
        );
    }
    s
}

/// A chain of `n` revolute joints as URDF.
fn urdf_chain(n: usize) -> String {
    let mut s = String::from("<robot name=\"chain\">\n<link name=\"l0\"/>\n");
    for i in 1..=n {
        s += &format!(
            "<link name=\"l{i}\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" \
             iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>\n<joint name=\"j{i}\" type=\"continuous\">\
             <parent link=\"l{}\"/><child link=\"l{i}\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 0 1\"/></joint>\n",
            i - 1
        );
    }
    s + "</robot>\n"
}

/// Stack-depth probes: deeply nested YAML and XML, and very long chains.
#[test]
fn deep_inputs_do_not_overflow_the_stack() {
    on_small_stack(|| {
        let deep = 100_000;
        let cases: Vec<(&str, String, Format, Expect)> = vec![
            (
                "100k [",
                "[".repeat(deep),
                Format::Yaml,
                Expect::Error("probe.yaml"),
            ),
            (
                "100k [ ] closed",
                format!("name: {}{}", "[".repeat(deep), "]".repeat(deep)),
                Format::Yaml,
                Expect::Error("probe.yaml"),
            ),
            (
                "100k {a: ",
                "{a: ".repeat(deep),
                Format::Yaml,
                Expect::Error("probe.yaml"),
            ),
            (
                "100k - ",
                "- ".repeat(deep),
                Format::Yaml,
                Expect::Error("probe.yaml"),
            ),
            (
                "100k nested XML",
                format!("<robot>{}{}</robot>", "<a>".repeat(deep), "</a>".repeat(deep)),
                Format::Urdf,
                Expect::Error("probe.urdf"),
            ),
            (
                "100k unclosed XML",
                "<robot>".repeat(deep),
                Format::Urdf,
                Expect::Error("probe.urdf"),
            ),
            (
                "10k-link YAML chain",
                yaml_chain(10_000),
                Format::Yaml,
                Expect::Accepted,
            ),
            (
                "10k-link URDF chain",
                urdf_chain(10_000),
                Format::Urdf,
                Expect::Accepted,
            ),
        ];
        for (name, text, format, expect) in cases {
            check_case(name, text, format, expect);
        }
    });
}

/// Inputs the fuzzer found (or that probe a limit), kept as regression cases: loaded, and
/// generated when accepted.
#[test]
fn fuzz_regressions() {
    let dir = workspace_root().join("codegen/tests/data/fuzz");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .map(|d| d.map(|e| e.expect("entry").path()).collect())
        .unwrap_or_default();
    files.sort();
    for path in files {
        let format = match path.extension().and_then(|e| e.to_str()) {
            Some("yaml") => Format::Yaml,
            Some("urdf") => Format::Urdf,
            _ => continue,
        };
        let bytes = std::fs::read(&path).expect("readable");
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let shown = path.display().to_string();
        on_small_stack(move || {
            let start = Instant::now();
            let accepted = check_input(&text, format, Path::new("probe"))
                .unwrap_or_else(|p| panic!("{shown}: {p}"))
                .is_some();
            assert!(
                start.elapsed() < Duration::from_secs(5),
                "{shown}: took {:?}",
                start.elapsed()
            );
            // Accepted: the whole generator must give code or an error, not panic.
            if accepted {
                let generated = std::panic::catch_unwind(|| {
                    dyngen_codegen::generate::generate_robot(&path, "probe", "Probe", "test").map(|_| ())
                });
                assert!(generated.is_ok(), "{shown}: generation panicked");
            }
        });
    }
}

fn runner(cases: u32) -> TestRunner {
    TestRunner::new(Config {
        cases,
        failure_persistence: None,
        source_file: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(0xF022_7EE5),
        ..Config::default()
    })
}

/// `a` and `b` are the same model up to rounding of the printed numbers (joints by name: the
/// loader orders them depth-first, the random model need not).
fn same_model(a: &Model, b: &Model) -> Result<(), String> {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs()));
    let close_all = |x: &[f64], y: &[f64]| x.len() == y.len() && x.iter().zip(y).all(|(x, y)| close(*x, *y));
    if a.dof() != b.dof() || !close_all(a.gravity().as_slice(), b.gravity().as_slice()) {
        return Err("dof or gravity".into());
    }
    for (i, ja) in a.joints().iter().enumerate() {
        let k = b
            .joints()
            .iter()
            .position(|j| j.name == ja.name)
            .ok_or(format!("joint {} lost", ja.name))?;
        let jb = &b.joints()[k];
        let parent = |m: &Model, p: Option<usize>| p.map(|p| m.joints()[p].name.clone());
        let ok = parent(a, ja.parent) == parent(b, jb.parent)
            && ja.kind == jb.kind
            && ja.limits == jb.limits
            && close_all(ja.axis.as_slice(), jb.axis.as_slice())
            && close_all(ja.origin.rotation.as_slice(), jb.origin.rotation.as_slice())
            && close_all(ja.origin.translation.as_slice(), jb.origin.translation.as_slice())
            && close_all(
                &a.bodies()[i].inertia.parameters(),
                &b.bodies()[k].inertia.parameters(),
            );
        if !ok {
            return Err(format!("joint {} or its body differs", ja.name));
        }
    }
    let (ea, eb) = (&a.end_effector(), &b.end_effector());
    if a.joints()[a.end_effector_body()].name != b.joints()[b.end_effector_body()].name
        || !close_all(ea.placement.rotation.as_slice(), eb.placement.rotation.as_slice())
        || !close_all(
            ea.placement.translation.as_slice(),
            eb.placement.translation.as_slice(),
        )
    {
        return Err("end-effector differs".into());
    }
    Ok(())
}

/// Random valid trees, written as YAML and as URDF, load back to the same model; a few are
/// generated.
#[test]
fn random_trees_round_trip_through_yaml_and_urdf() {
    let count = std::cell::Cell::new(0);
    let result = runner(128).run(&arb_model(8), |model| {
        count.set(count.get() + 1);
        let yaml = to_yaml(&model);
        let loaded = load_yaml_str(&yaml, Path::new("tree.yaml"))
            .map_err(|e| proptest::test_runner::TestCaseError::fail(format!("YAML rejected: {e}\n{yaml}")))?;
        same_model(&model, &loaded.model)
            .map_err(|e| proptest::test_runner::TestCaseError::fail(format!("YAML: {e}\n{yaml}")))?;
        let urdf = to_urdf(&model);
        let options = Choices {
            end_effector: Some(FrameSpec::link(model.end_effector().name.clone())),
            gravity: Some(model.gravity().into()),
            ..Choices::default()
        };
        let from_urdf = load_urdf_str(&urdf, Path::new("tree.urdf"), &options)
            .map_err(|e| proptest::test_runner::TestCaseError::fail(format!("URDF rejected: {e}\n{urdf}")))?;
        same_model(&model, &from_urdf.model)
            .map_err(|e| proptest::test_runner::TestCaseError::fail(format!("URDF: {e}\n{urdf}")))?;
        if count.get() % 16 == 0 {
            check_generation(&loaded.model).map_err(proptest::test_runner::TestCaseError::fail)?;
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Found by the long run (seed 1): a model whose numbers are finite but so large that folding
/// constants overflowed made the emitter panic. Huge item values and a huge gravity are now
/// loader errors. (Gravity was bounded when generated code came to fold the parameters a robot's
/// torques cannot depend on: this robot's mass, the factor that overflowed, left the code, and
/// a gravity of -1e308 would have been generated without a word.)
#[test]
fn overflowing_models_are_errors_not_panics() {
    // Also kept as data: tests/data/fuzz/overflow-gravity.yaml.
    let scratch = dyngen_testkit::scratch::scratch_dir("overflow");
    let dir = scratch.path();
    let base = "\
name: huge
gravity: [0.0, 0.0, -9.81]
links:
  - name: base
  - name: l1
    inertial:
      mass: 2.0
      inertia: { ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }
joints:
  - { name: j1, type: continuous, parent: base, child: l1, axis: [1, 0, 0], origin: { xyz: [0, 0, 0.1] } }
";
    let cases = [
        ("-9.81]", "-1e308]", "beyond ±1e12"),
        ("mass: 2.0", "mass: 1e300", "beyond ±1e12"),
        ("ixx: 0.1, ixy: 0.0", "ixx: 1e200, ixy: 0.0", "beyond ±1e12"),
        ("xyz: [0, 0, 0.1]", "xyz: [0, 0, 1e200]", "beyond ±1e12"),
    ];
    for (from, to, expected) in cases {
        let path = dir.join("huge.yaml");
        std::fs::write(&path, base.replacen(from, to, 1)).expect("write");
        let result = std::panic::catch_unwind(|| {
            dyngen_codegen::generate::generate_robot(&path, "huge.yaml", "Huge", "test").map(|_| ())
        })
        .unwrap_or_else(|_| panic!("{to}: generation panicked"));
        let e = result.expect_err(to).to_string();
        assert!(e.contains("huge.yaml") && e.contains(expected), "{to}: {e}");
    }
}

/// A description with thousands of joints loads (see above), but generating it would run for
/// hours: a module estimated above `MAX_GENERATED_BYTES` is a clear error, at once.
#[test]
fn too_many_joints_is_an_error_not_a_hang() {
    use dyngen_codegen::generate::generate_robot;
    let scratch = dyngen_testkit::scratch::scratch_dir("dof");
    let dir = scratch.path();
    let path = dir.join("long.yaml");
    std::fs::write(&path, yaml_chain(2_000)).expect("write");
    let start = Instant::now();
    let e = generate_robot(&path, "long.yaml", "Long", "test").expect_err("too many joints");
    assert!(start.elapsed() < Duration::from_secs(5));
    let e = e.to_string();
    assert!(
        e.contains("long.yaml") && e.contains("2000 moving joints") && e.contains("more than dyngen writes"),
        "{e}"
    );
}
