//! The build-script API: generate a robot into `OUT_DIR` from a downstream crate's `build.rs`,
//! in the style of `prost-build`.
//!
//! In `build.rs`, `fn main() { dyngen_codegen::compile_robot("robots/panda.yaml"); }`; in
//! `src/lib.rs`, `dyngen_runtime::include_robot!(panda);` gives `panda::Panda`.

use crate::description::{DescriptionError, FrameSelection, NonPhysicalInertia, UrdfOptions};
use crate::generate::{generate_robot_with, module_name, type_name, write_file, GenerateError, RobotReport};
use crate::{FunctionGroup, Functions};
use std::path::{Path, PathBuf};

/// Generates `description` into `$OUT_DIR/<module>.rs` with the defaults of [`Builder`]; on
/// error, prints the message for a person and fails the build (no backtrace).
pub fn compile_robot(description: impl AsRef<Path>) {
    Builder::new(description).compile_or_exit();
}

/// Options for generating one robot from a build script.
#[derive(Clone, Debug)]
pub struct Builder {
    description: PathBuf,
    out_dir: Option<PathBuf>,
    output_file: Option<PathBuf>,
    module: Option<String>,
    regenerate: Option<String>,
    type_name: Option<String>,
    cargo_directives: bool,
    urdf: UrdfOptions,
    functions: Option<Vec<FunctionGroup>>,
}

impl Builder {
    /// A robot description (`.yaml` or `.urdf`), relative to the crate's manifest directory.
    pub fn new(description: impl AsRef<Path>) -> Builder {
        Builder {
            description: description.as_ref().to_owned(),
            out_dir: None,
            output_file: None,
            module: None,
            regenerate: None,
            type_name: None,
            cargo_directives: true,
            urdf: UrdfOptions::default(),
            functions: None,
        }
    }

    /// For a bare URDF file: make origin angles within `tolerance` radians of a quarter turn
    /// exact quarter turns, and axis components that close to 0 exactly 0 (at most 1e-3; each
    /// change is reported as a warning). Vendor files often write `1.5708` for π/2, which leaves
    /// every rotation dense and the generated code slower. A YAML description sets
    /// `snap_angles:` itself (giving this option with one is an error).
    pub fn snap_angles(mut self, tolerance: f64) -> Builder {
        self.urdf.snap_angles = Some(tolerance);
        self
    }

    /// For a bare URDF file: what to do with a link whose inertia no real body can have
    /// (default [`NonPhysicalInertia::AsWritten`]: load it as written, with a warning;
    /// `Repair`: the nearest physical inertia, each change a note; `Strict`: an error). A YAML
    /// description sets `inertia:` itself (giving this option with one is an error).
    pub fn inertia(mut self, choice: NonPhysicalInertia) -> Builder {
        self.urdf.inertia = choice;
        self
    }

    /// For a bare URDF file: the root link flies free (a legged robot, a humanoid): the robot
    /// is generated with `FloatingBaseDynamics` and `FloatingFrameKinematics`
    /// (`docs/floating_base.md`). A YAML description sets `floating_base:` itself.
    pub fn floating_base(mut self) -> Builder {
        self.urdf.floating_base = true;
        self
    }

    /// For a bare URDF file: the frames to generate besides the end-effector (a YAML
    /// description's `frames:`), e.g. `FrameSelection::AllLinks`.
    pub fn frames(mut self, frames: FrameSelection) -> Builder {
        self.urdf.frames = frames;
        self
    }

    /// For a bare URDF file: all the choices a YAML wrapper would make (end-effector frame,
    /// locked joints, gravity, snapping, non-physical inertias). A YAML description makes them
    /// itself.
    pub fn urdf_options(mut self, options: UrdfOptions) -> Builder {
        self.urdf = options;
        self
    }

    /// The groups of functions to generate besides kinematics and dynamics (default: what the
    /// description's `functions:` says, else [`Functions::default_for`](crate::Functions::default_for)
    /// its joints: every group up to
    /// [`EVERY_GROUP_BY_DEFAULT_UP_TO_DOF`](crate::EVERY_GROUP_BY_DEFAULT_UP_TO_DOF) joints).
    /// A description that chooses them itself and this option together are an error.
    pub fn functions(mut self, groups: &[FunctionGroup]) -> Builder {
        self.functions = Some(groups.to_vec());
        self
    }

    /// The directory to write `<module>.rs` into (default: `$OUT_DIR`).
    pub fn out_dir(mut self, dir: impl AsRef<Path>) -> Builder {
        self.out_dir = Some(dir.as_ref().to_owned());
        self
    }

    /// Write exactly this file instead of `<out_dir>/<module>.rs` (a command-line tool's
    /// `-o`); the module name then defaults to the file's stem. The write is the same: atomic,
    /// and never over a file dyngen did not write.
    pub fn output_file(mut self, file: impl AsRef<Path>) -> Builder {
        self.output_file = Some(file.as_ref().to_owned());
        self
    }

    /// The command the generated file's header says reproduces it (default: `cargo build
    /// (build.rs)`).
    pub fn regenerate_command(mut self, command: impl Into<String>) -> Builder {
        self.regenerate = Some(command.into());
        self
    }

    /// The file and module name (default: from the description's file name, `panda.yaml` → `panda`).
    pub fn module_name(mut self, name: impl Into<String>) -> Builder {
        self.module = Some(name.into());
        self
    }

    /// The generated type's name (default: the module name in CamelCase, `panda` → `Panda`).
    pub fn type_name(mut self, name: impl Into<String>) -> Builder {
        self.type_name = Some(name.into());
        self
    }

    /// Whether to print `cargo:rerun-if-changed` and `cargo:warning` lines (default: yes).
    pub fn cargo_directives(mut self, on: bool) -> Builder {
        self.cargo_directives = on;
        self
    }

    /// Generates the robot; returns the file written (or left as it was, if unchanged).
    pub fn compile(self) -> Result<PathBuf, GenerateError> {
        self.compile_report().map(|report| report.file)
    }

    /// [`Builder::compile`], returning everything a tool reports: the file, whether it was
    /// rewritten, and the generated robot (model, warnings, notes, operation counts, time).
    pub fn compile_report(self) -> Result<RobotReport, GenerateError> {
        let module = match (&self.module, &self.output_file) {
            (Some(module), _) => module.clone(),
            (None, Some(file)) => module_name(file),
            (None, None) => module_name(&self.description),
        };
        let file = match (&self.output_file, &self.out_dir) {
            (Some(file), _) => file.clone(),
            (None, Some(dir)) => dir.join(format!("{module}.rs")),
            (None, None) => std::env::var_os("OUT_DIR")
                .map(|dir| PathBuf::from(dir).join(format!("{module}.rs")))
                .ok_or_else(|| GenerateError::Io {
                    path: PathBuf::from("$OUT_DIR"),
                    source: std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        "not set: call this from a build script",
                    ),
                })?,
        };
        let ty = self.type_name.unwrap_or_else(|| type_name(&module));
        let shown = self.description.to_string_lossy().replace('\\', "/");
        if self.cargo_directives {
            // Printed before generating, so a fixed description re-runs the build after an error.
            println!("cargo:rerun-if-changed={}", self.description.display());
        }
        let regenerate = self
            .regenerate
            .unwrap_or_else(|| "cargo build (build.rs)".to_owned());
        let functions = match &self.functions {
            Some(groups) => Some(
                Functions::with(groups)
                    .map_err(|message| DescriptionError::new(&self.description, message))?,
            ),
            None => None,
        };
        let robot = generate_robot_with(&self.description, &shown, &ty, &regenerate, &self.urdf, functions)?;
        if self.cargo_directives {
            for source in &robot.sources {
                println!("cargo:rerun-if-changed={}", source.display());
            }
            for warning in &robot.warnings {
                println!("cargo:warning={warning}");
            }
        }
        let outcome = write_file(&file, &robot.code)?;
        Ok(RobotReport {
            module,
            file,
            robot,
            outcome,
        })
    }

    /// [`Builder::compile`], printing an error as a person reads it and exiting non-zero.
    pub fn compile_or_exit(self) -> PathBuf {
        match self.compile() {
            Ok(file) => file,
            Err(e) => {
                eprintln!("error: dyngen could not generate the robot: {e}");
                std::process::exit(1)
            }
        }
    }
}
