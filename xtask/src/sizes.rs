//! `cargo xtask sizes`: generated code size and release compile time per group of functions, as
//! the robot grows (docs/performance-notes.md, *Code size and compile time*).
//!
//! Robots: the random chains of `dyngen_testkit::scale` with 7, 12, 20 and 30 joints and its
//! tree of four 8-joint branches (32 joints). Per robot, the module with kinematics and dynamics
//! only, then that plus each other group (base parameters with the regressors they need), the
//! default selection and every group. Each module is compiled in release in a scratch crate that
//! holds only it (`target/sizes/`, its dependencies built beforehand, untimed); the time is the
//! wall time of that `cargo build`.

use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::Choices;
use dyngen_codegen::generate::shapes;
use dyngen_codegen::internals::generate::{emit, trace_functions, Provenance, MODULE_ATTRIBUTES};
use dyngen_codegen::model::Model;
use dyngen_codegen::{FunctionGroup, Functions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// What to compile (generation and sizes are always measured).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Compile {
    /// Nothing: sizes and generation times only.
    None,
    /// Every module.
    All,
}

/// The selections reported per robot, by name.
fn selections(dof: usize) -> Vec<(String, Functions)> {
    use FunctionGroup as G;
    let with = |groups: &[G]| Functions::with(groups).expect("valid selection");
    let mut out = vec![("kinematics + dynamics".to_owned(), with(&[]))];
    for (name, groups) in [
        ("+ regressors", &[G::Regressors][..]),
        (
            "+ regressors + base_parameters",
            &[G::Regressors, G::BaseParameters],
        ),
        ("+ forward_dynamics", &[G::ForwardDynamics]),
        ("+ derivatives", &[G::Derivatives]),
        ("+ frames", &[G::Frames]),
    ] {
        out.push((name.to_owned(), with(groups)));
    }
    out.push((
        format!("default ({})", Functions::default_for(dof)),
        Functions::default_for(dof),
    ));
    out.push(("all".to_owned(), Functions::all()));
    out
}

fn robots() -> Vec<(String, Model)> {
    use dyngen_testkit::scale::{chain, tree};
    let mut out: Vec<(String, Model)> = [7, 12, 20, 30]
        .into_iter()
        .map(|n| (format!("chain, {n} DOF"), chain(n)))
        .collect();
    out.push(("tree of 4 × 8, 32 DOF".to_owned(), tree(32)));
    out
}

/// A crate holding one generated module, `src/robot.rs`.
struct Scratch {
    dir: PathBuf,
}

impl Scratch {
    fn new(root: &Path) -> Result<Scratch, String> {
        let dir = root.join("target/sizes/crate");
        std::fs::create_dir_all(dir.join("src")).map_err(|e| e.to_string())?;
        let runtime = root.join("runtime");
        let manifest = format!(
            "[package]\nname = \"sizes-scratch\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n\
             [dependencies]\ndyngen-runtime = {{ path = {:?} }}\n\n[workspace]\n",
            runtime.display().to_string()
        );
        std::fs::write(dir.join("Cargo.toml"), manifest).map_err(|e| e.to_string())?;
        std::fs::write(
            dir.join("src/lib.rs"),
            format!("{MODULE_ATTRIBUTES}\npub mod robot;\n"),
        )
        .map_err(|e| e.to_string())?;
        let scratch = Scratch { dir };
        // Dependencies once, untimed, with an empty module.
        scratch.compile("")?;
        Ok(scratch)
    }

    /// Release-compiles `code` as the crate's module; the wall time in seconds.
    fn compile(&self, code: &str) -> Result<f64, String> {
        std::fs::write(self.dir.join("src/robot.rs"), code).map_err(|e| e.to_string())?;
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let start = Instant::now();
        let out = Command::new(cargo)
            .current_dir(&self.dir)
            .args(["build", "--release", "--quiet"])
            .env("CARGO_TARGET_DIR", self.dir.join("target"))
            .env_remove("RUSTFLAGS")
            .output()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "the module does not compile:\n{}",
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(start.elapsed().as_secs_f64())
    }
}

/// The table, one row per robot and selection.
pub fn report(root: &Path, compile: Compile, max_mib: f64) -> Result<String, String> {
    let scratch = match compile {
        Compile::None => None,
        Compile::All => Some(Scratch::new(root)?),
    };
    let mut table = String::from(
        "| robot | functions | generated | generation | release compile |\n|---|---|---|---|---|\n",
    );
    for (name, model) in robots() {
        let base = BaseParameterSet::compute(&model);
        for (selection, functions) in selections(model.dof()) {
            let start = Instant::now();
            let (shapes, _) = shapes(&model, functions, &Choices::default());
            let traced = trace_functions(&model, base.clone(), functions, &shapes);
            let provenance = Provenance {
                source: name.clone(),
                source_hash: "0".into(),
                regenerate: "cargo xtask sizes".into(),
                type_name: "Robot".into(),
            };
            let code = emit(&model, &traced, &provenance);
            let generation = start.elapsed().as_secs_f64();
            let mib = code.len() as f64 / (1024.0 * 1024.0);
            let compiled = match &scratch {
                Some(s) if mib <= max_mib => format!("{:.1} s", s.compile(&code)?),
                Some(_) => format!("not compiled (over {max_mib} MiB)"),
                None => "—".to_owned(),
            };
            let row = format!("| {name} | {selection} | {mib:.2} MiB | {generation:.2} s | {compiled} |");
            eprintln!("{row}");
            let _ = writeln!(table, "{row}");
        }
    }
    Ok(table)
}
