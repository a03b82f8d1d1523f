//! Builds what the tests look at, once: three robots generated as C libraries by the
//! `Builder` (the Panda, the floating Solo-12, and a 2-DOF arm with kinematics and dynamics
//! only), their states, and the C and C++ programs of `tests/downstream/c_library/` built
//! against their CMake packages (cargo's dev profile, one target directory for the three),
//! then run.

use super::super::generated_crate::workspace_root;
use dyngen_codegen::model::Model;
use dyngen_codegen::{Builder, FunctionGroup};
use dyngen_runtime::SplitMix64;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// States per robot: one batch of four in lanes, and two more one at a time.
pub(super) const STATES: usize = 6;

/// One robot's C library.
pub(super) struct Library {
    pub prefix: &'static str,
    pub dir: PathBuf,
    pub model: Model,
    pub functions: Vec<FunctionGroup>,
    /// Its inputs, by name, `STATES` states each.
    pub states: Vec<(&'static str, usize, Vec<f64>)>,
}

impl Library {
    /// The input `name` of state `s`.
    pub fn input(&self, name: &str, s: usize) -> &[f64] {
        let (_, len, values) = (self.states.iter().find(|(n, ..)| *n == name))
            .unwrap_or_else(|| panic!("{}: no input {name}", self.prefix));
        &values[s * len..(s + 1) * len]
    }

    pub fn header(&self) -> String {
        let path = self.dir.join(format!("include/{}_dynamics.h", self.prefix));
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }
}

/// What the programs wrote and said.
pub(super) struct Run {
    pub libraries: Vec<Library>,
    pub c: Output,
    pub c_results: String,
    pub cpp: Output,
    pub cpp_results: String,
    pub work: PathBuf,
}

/// Everything, built and run once for every test that looks at it.
pub(super) fn run() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(build_and_run)
}

/// Where the libraries, the build tree and cargo's target directory live: under the
/// workspace's `target/`, so that a failure can be looked at and a second run is quick.
fn work_dir() -> PathBuf {
    workspace_root().join("target/c-library")
}

fn generate(description: &str, prefix: &'static str, functions: Option<&[FunctionGroup]>) -> Library {
    let root = workspace_root();
    let dir = work_dir().join("robots").join(prefix);
    let mut builder = Builder::new(root.join(description))
        .c_library(&dir)
        .c_prefix(prefix)
        .c_runtime_path(root.join("runtime"))
        .cargo_directives(false);
    if let Some(groups) = functions {
        builder = builder.functions(groups);
    }
    let report = builder.compile_report().unwrap_or_else(|e| panic!("{e}"));
    // The workspace's versions of nalgebra and the rest, already in the local registry cache:
    // an offline build needs nothing new.
    std::fs::copy(root.join("Cargo.lock"), dir.join("Cargo.lock")).expect("Cargo.lock");
    let functions = report.robot.functions.groups().collect();
    let model = report.robot.model;
    let states = states(&model, report.robot.base_parameter_count);
    Library {
        prefix,
        dir,
        model,
        functions,
        states,
    }
}

/// Random states of every input a function of `model` takes.
fn states(model: &Model, base_parameters: usize) -> Vec<(&'static str, usize, Vec<f64>)> {
    let mut rng = SplitMix64::new(model.nq() as u64);
    let floating = model.floating_base().is_some();
    let (nq, nv) = (model.nq(), model.nv());
    let parameters = match floating {
        true => dyngen_codegen::dynamics::FloatingDynamics::parameter_names(model).len(),
        false => model.parameter_count(),
    };
    let mut q = Vec::new();
    for _ in 0..STATES {
        let mut state: Vec<f64> = (0..nq).map(|_| rng.uniform((-2.0, 2.0))).collect();
        if floating {
            let norm = state[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            state[3..7].iter_mut().for_each(|x| *x /= norm);
        }
        q.extend(state);
    }
    let mut random = |len: usize, range: (f64, f64)| (0..STATES * len).map(|_| rng.uniform(range)).collect();
    vec![
        ("q", nq, q),
        ("qd", nv, random(nv, (-2.0, 2.0))),
        ("v", nv, random(nv, (-2.0, 2.0))),
        ("a", nv, random(nv, (-4.0, 4.0))),
        ("qdd", nv, random(nv, (-4.0, 4.0))),
        ("tau", nv, random(nv, (-20.0, 20.0))),
        ("parameters", parameters, random(parameters, (-1.0, 1.0))),
        (
            "base_parameters",
            base_parameters,
            random(base_parameters, (-1.0, 1.0)),
        ),
        ("r", nv, random(nv, (-1.0, 1.0))),
    ]
}

fn write_states(library: &Library, path: &Path) {
    let mut text = format!("robot {} {STATES}\n", library.prefix);
    for (name, len, values) in &library.states {
        let _ = write!(text, "{name} {}", len * STATES);
        for v in values {
            let _ = write!(text, " {v:?}");
        }
        text.push('\n');
    }
    std::fs::write(path, text).expect("states");
}

/// The table's functions as the header declares them: for each `#define P_FUNCTION_<NAME>`,
/// the declaration of `P_<name>` (whether it takes a frame, its inputs and outputs).
pub(super) fn declarations(library: &Library) -> Vec<(String, bool, usize, usize)> {
    let header = library.header();
    let macro_prefix = format!("#define {}_FUNCTION_", library.prefix.to_ascii_uppercase());
    let mut found = Vec::new();
    for line in header.lines().filter_map(|l| l.strip_prefix(&macro_prefix)) {
        let name = line
            .split_whitespace()
            .next()
            .expect("a name")
            .to_ascii_lowercase();
        if name == "count" {
            continue;
        }
        let start = format!("int32_t {}_{name}(", library.prefix);
        let declaration = (header.lines().find(|l| l.starts_with(&start)))
            .unwrap_or_else(|| panic!("{}: no declaration of {name}", library.prefix));
        let parameters = &declaration[start.len()..];
        let takes_frame = parameters.starts_with("size_t frame");
        let inputs = parameters.matches("const double *").count();
        let outputs = parameters.matches("double *").count() - inputs;
        found.push((name, takes_frame, inputs, outputs));
    }
    found
}

/// `calls.c`: the registry of linked robots, each entry called through its own function.
fn registry(libraries: &[Library]) -> String {
    let mut text = String::from(
        "/* Written by tests/suite/c_library: the robots linked into the test programs. */\n\
         #include \"harness.h\"\n",
    );
    for library in libraries {
        let p = library.prefix;
        let _ = writeln!(text, "#include \"{p}_dynamics.h\"");
        let _ = write!(
            text,
            "\nstatic int32_t {p}_call(size_t function, size_t frame, const double *const *in, double *const *out) {{\n\
             \x20   (void)frame;\n    switch (function) {{\n"
        );
        for (name, takes_frame, inputs, outputs) in declarations(library) {
            let mut arguments: Vec<String> = Vec::new();
            if takes_frame {
                arguments.push("frame".into());
            }
            arguments.extend((0..inputs).map(|k| format!("in[{k}]")));
            arguments.extend((0..outputs).map(|k| format!("out[{k}]")));
            let _ = writeln!(
                text,
                "    case {}_FUNCTION_{}: return {p}_{name}({});",
                p.to_ascii_uppercase(),
                name.to_ascii_uppercase(),
                arguments.join(", ")
            );
        }
        text += "    }\n    return -1;\n}\n";
    }
    text += "\nconst harness_robot harness_robots[] = {\n";
    for library in libraries {
        let p = library.prefix;
        let symbols = [
            "abi_version",
            "robot_name",
            "is_floating_base",
            "dof",
            "nq",
            "nv",
            "parameter_count",
            "base_parameter_count",
            "frame_count",
            "function_count",
            "joint_name",
            "parameter_name",
            "base_parameter_name",
            "frame_name",
            "status_message",
            "parameters",
            "base_parameters",
            "joint_limits",
            "function_info",
            "evaluate",
            "call",
        ];
        let symbols: Vec<String> = symbols.iter().map(|s| format!("{p}_{s}")).collect();
        let _ = writeln!(text, "    {{\"{p}\", {}}},", symbols.join(", "));
    }
    let _ = writeln!(
        text,
        "}};\nconst size_t harness_robot_count = {};",
        libraries.len()
    );
    text
}

fn command(program: impl AsRef<std::ffi::OsStr>, args: &[&dyn AsRef<std::ffi::OsStr>]) -> Command {
    let mut command = Command::new(program);
    command.args(args.iter().map(|a| a.as_ref()));
    command
}

/// Runs `command`, failing the test with its output when it fails.
fn checked(mut command: Command, what: &str) -> Output {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {command:?}: {e} (cmake, a C/C++ compiler and Eigen are needed: `apt-get install -y cmake libeigen3-dev pkg-config`)"));
    assert!(
        output.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn build_and_run() -> Run {
    let libraries = vec![
        generate("robots/panda.yaml", "panda", None),
        generate("robots/solo12.yaml", "solo12", None),
        generate(
            "codegen/tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf",
            "two_dof",
            Some(&[]),
        ),
    ];
    let work = work_dir();
    let (build, data) = (work.join("build"), work.join("data"));
    std::fs::create_dir_all(&data).expect("data directory");
    let states: Vec<PathBuf> = (libraries.iter())
        .map(|library| {
            let path = data.join(format!("{}.states", library.prefix));
            write_states(library, &path);
            path
        })
        .collect();
    let calls = data.join("calls.c");
    std::fs::write(&calls, registry(&libraries)).expect("calls.c");

    let join = |parts: Vec<String>| parts.join(";");
    let prefix_path = join(libraries.iter().map(|l| l.dir.display().to_string()).collect());
    let robots = join(libraries.iter().map(|l| l.prefix.to_owned()).collect());
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let source = workspace_root().join("tests/downstream/c_library");
    let mut configure = command(
        "cmake",
        &[
            &"-S",
            &source,
            &"-B",
            &build,
            &format!("-DCMAKE_PREFIX_PATH={prefix_path}"),
            &format!("-DDYNGEN_TEST_ROBOTS={robots}"),
            &format!("-DDYNGEN_TEST_CALLS={}", calls.display()),
            &format!("-DDYNGEN_CARGO={cargo}"),
            &"-DDYNGEN_CARGO_PROFILE=dev",
            &format!("-DDYNGEN_CARGO_TARGET_DIR={}", work.join("cargo").display()),
        ],
    );
    configure.env("CARGO_NET_OFFLINE", "true");
    checked(configure, "cmake (configure)");
    let mut compile = command("cmake", &[&"--build", &build, &"-j", &"2"]);
    compile.env("CARGO_NET_OFFLINE", "true");
    checked(compile, "cmake --build");

    let (c_results, cpp_results) = (data.join("c.results"), data.join("cpp.results"));
    let run_program = |program: &str, results: &Path| {
        let mut args: Vec<&dyn AsRef<std::ffi::OsStr>> = vec![&results];
        args.extend(states.iter().map(|s| s as &dyn AsRef<std::ffi::OsStr>));
        command(build.join(program), &args).output().expect(program)
    };
    let c = run_program("check_c", &c_results);
    let cpp = run_program("check_cpp", &cpp_results);
    let read = |path: &Path| std::fs::read_to_string(path).unwrap_or_default();
    Run {
        c_results: read(&c_results),
        cpp_results: read(&cpp_results),
        libraries,
        c,
        cpp,
        work,
    }
}
