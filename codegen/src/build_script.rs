//! The build-script API: generate a robot into `OUT_DIR` from a downstream crate's `build.rs`,
//! in the style of `prost-build`.
//!
//! In `build.rs`, `fn main() { dyngen_codegen::compile_robot("robots/panda.yaml"); }`; in
//! `src/lib.rs`, `dyngen_runtime::include_robot!(panda);` gives `panda::Panda`.

use crate::c_library::{check_library, library_files, module_file, write_library, CLibrary, Naming};
use crate::description::{
    Choices, CodeShape, ContactSpec, DescriptionError, FrameReferences, FrameSelection, FrameSpec,
    JointParameters, NonPhysicalInertia,
};
use crate::generate::{
    check_file, generate_robot_with, module_name, type_name, write_file, GenerateError, RobotReport,
    WriteOutcome,
};
use crate::{FunctionGroup, Functions};
use std::path::{Path, PathBuf};

/// Generates `description` into `$OUT_DIR/<module>.rs` with the defaults of [`Builder`]; on
/// error, prints the message for a person and fails the build (no backtrace).
pub fn compile_robot(description: impl AsRef<Path>) {
    Builder::new(description).compile_or_exit();
}

/// Options for generating one robot from a build script: where the module goes and what it
/// is called, and the user's [`Choices`] on top of the description.
///
/// Each choice setter sets one field of the [`Choices`] (whose docs say what each does), so
/// the setters combine in any order; [`Builder::choices`] sets every field a whole value
/// chooses. For a bare URDF every choice comes from here; a YAML description makes its own,
/// and a key chosen both in it and here is an error naming the key (never a silent
/// preference).
///
/// ```no_run
/// use dyngen_codegen::description::FrameSelection;
/// use dyngen_codegen::{Builder, FunctionGroup};
/// Builder::new("urdf/kr210.urdf")
///     .end_effector("tool0")
///     .frames(FrameSelection::AllLinks)
///     .snap_angles(1e-4)
///     .functions(&[FunctionGroup::Regressors, FunctionGroup::ForwardDynamics])
///     .compile_or_exit();
/// ```
#[derive(Clone, Debug)]
pub struct Builder {
    description: PathBuf,
    out_dir: Option<PathBuf>,
    output_file: Option<PathBuf>,
    module: Option<String>,
    regenerate: Option<String>,
    type_name: Option<String>,
    cargo_directives: bool,
    /// Where to write the robot as a C library, with the prefix and runtime chosen for it.
    c_library: Option<PathBuf>,
    c_prefix: Option<String>,
    c_runtime_path: Option<PathBuf>,
    choices: Choices,
    /// Why the groups given to [`Builder::functions`] cannot be generated together (a group
    /// without one it needs); reported by [`Builder::compile`].
    invalid_functions: Option<String>,
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
            c_library: None,
            c_prefix: None,
            c_runtime_path: None,
            choices: Choices::default(),
            invalid_functions: None,
        }
    }

    /// Sets [`Choices::end_effector`]: a link name (`.end_effector("tool0")`) or a
    /// [`FrameSpec`] (a frame at an offset from a link).
    pub fn end_effector(mut self, frame: impl Into<FrameSpec>) -> Builder {
        self.choices.end_effector = Some(frame.into());
        self
    }

    /// Sets [`Choices::frames`], e.g. [`FrameSelection::AllLinks`].
    pub fn frames(mut self, frames: FrameSelection) -> Builder {
        self.choices.frames = frames;
        self
    }

    /// Adds a joint to [`Choices::locked_joints`], made rigid at `position` (radians or
    /// metres); one call per joint (locking a joint twice is an error).
    pub fn locked_joint(mut self, joint: impl Into<String>, position: f64) -> Builder {
        self.choices.locked_joints.push((joint.into(), position));
        self
    }

    /// Sets [`Choices::gravity`] (m/s², in the base frame).
    pub fn gravity(mut self, gravity: [f64; 3]) -> Builder {
        self.choices.gravity = Some(gravity);
        self
    }

    /// Sets [`Choices::snap_angles`]: angles within `tolerance` radians of a quarter turn
    /// made exact, each change a note.
    pub fn snap_angles(mut self, tolerance: f64) -> Builder {
        self.choices.snap_angles = Some(tolerance);
        self
    }

    /// Sets [`Choices::inertia`]: what to do with a link whose inertia no real body can have.
    pub fn inertia(mut self, choice: NonPhysicalInertia) -> Builder {
        self.choices.inertia = choice;
        self
    }

    /// Sets [`Choices::floating_base`]: the root link flies free, and each chosen group is
    /// generated as its floating-base trait (`FloatingBaseDynamics`, `FloatingFrameKinematics`,
    /// …; `docs/floating_base.md`).
    pub fn floating_base(mut self) -> Builder {
        self.choices.floating_base = true;
        self
    }

    /// Sets [`Choices::joint_parameters`]: joint-level regressor columns and values.
    pub fn joint_parameters(mut self, parameters: JointParameters) -> Builder {
        self.choices.joint_parameters = Some(parameters);
        self
    }

    /// Adds to [`Choices::contacts`]: `frame` held to the world, e.g.
    /// `.contact(ContactSpec::new("FL_FOOT", ContactKind::Point))`; the robot is then generated
    /// with `ContactDynamics` (`docs/contacts.md`).
    pub fn contact(mut self, contact: ContactSpec) -> Builder {
        self.choices.contacts.push(contact);
        self
    }

    /// Sets [`Choices::functions`]: the groups of functions to generate besides kinematics
    /// and dynamics (default: what the description's `functions:` says, else
    /// [`Functions::default_for`] its joints: every group up to
    /// [`EVERY_GROUP_BY_DEFAULT_UP_TO_DOF`](crate::EVERY_GROUP_BY_DEFAULT_UP_TO_DOF) joints).
    /// Groups that cannot go together (`base_parameters` without `regressors`) make
    /// [`Builder::compile`] fail with the reason.
    pub fn functions(mut self, groups: &[FunctionGroup]) -> Builder {
        match Functions::with(groups) {
            Ok(functions) => {
                self.choices.functions = Some(functions);
                self.invalid_functions = None;
            }
            Err(message) => {
                self.choices.functions = None;
                self.invalid_functions = Some(message);
            }
        }
        self
    }

    /// Sets [`Choices::frame_references`]: which reference frames of the frame functions are
    /// straight-line code of their own (`FrameReferences::Aligned`: `local_world_aligned`,
    /// the others converted from it at run time).
    pub fn frame_references(mut self, choice: FrameReferences) -> Builder {
        self.choices.frame_references = choice;
        self
    }

    /// Sets [`Choices::code_shape`]: whether the functions that have a composed form (forward
    /// dynamics, `D⁻¹`, the derivatives of forward dynamics) are straight-line code
    /// (`CodeShape::Flat`) or computed from the robot's smaller functions
    /// (`CodeShape::Composed`).
    pub fn code_shape(mut self, choice: CodeShape) -> Builder {
        self.choices.code_shape = choice;
        self
    }

    /// Sets every field that `choices` chooses ([`Choices::chosen_keys`]: those that are not
    /// the default), as the field setters would; the other fields keep what was set before or
    /// after, in any order. E.g. the choices of a URDF export
    /// ([`UrdfExport::choices`](crate::description::UrdfExport::choices)), or a command line's.
    pub fn choices(mut self, choices: Choices) -> Builder {
        if choices.functions.is_some() {
            self.invalid_functions = None;
        }
        self.choices = self.choices.with(choices);
        self
    }

    /// The choices set so far: what [`Builder::compile`] generates the description with.
    pub fn chosen(&self) -> &Choices {
        &self.choices
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

    /// Also write the robot as a C library into `dir` (`docs/c-library.md`): a crate around
    /// the generated module (at `dir/src/robot.rs`) exporting `extern "C"` functions, its
    /// headers, a CMake package and a pkg-config file. The module is then written only there,
    /// unless [`Builder::output_file`] or [`Builder::out_dir`] also name a place for it. The
    /// directory must be new, empty or one dyngen wrote.
    pub fn c_library(mut self, dir: impl AsRef<Path>) -> Builder {
        self.c_library = Some(dir.as_ref().to_owned());
        self
    }

    /// The prefix of the C library's symbols (`<prefix>_mass_matrix`) and the name of its
    /// package (`<prefix>_dynamics`); default: the module name. Two robots linked into one
    /// program need two prefixes.
    pub fn c_prefix(mut self, prefix: impl Into<String>) -> Builder {
        self.c_prefix = Some(prefix.into());
        self
    }

    /// Make the C library's crate depend on `dyngen-runtime` at `path` (a checkout's
    /// `runtime/`) rather than on its published version.
    pub fn c_runtime_path(mut self, path: impl AsRef<Path>) -> Builder {
        self.c_runtime_path = Some(path.as_ref().to_owned());
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
        // With a C library and no other place named, the module lives in the library only.
        let file = match (&self.output_file, &self.out_dir, &self.c_library) {
            (Some(file), _, _) => Some(file.clone()),
            (None, Some(dir), _) => Some(dir.join(format!("{module}.rs"))),
            (None, None, Some(_)) => None,
            (None, None, None) => Some(
                std::env::var_os("OUT_DIR")
                    .map(|dir| PathBuf::from(dir).join(format!("{module}.rs")))
                    .ok_or_else(|| GenerateError::Io {
                        path: PathBuf::from("$OUT_DIR"),
                        source: std::io::Error::new(
                            std::io::ErrorKind::NotFound,
                            "not set: call this from a build script",
                        ),
                    })?,
            ),
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
        if let Some(message) = self.invalid_functions {
            return Err(DescriptionError::new(&self.description, message).into());
        }
        let robot = generate_robot_with(&self.description, &shown, &ty, &regenerate, &self.choices)?;
        if self.cargo_directives {
            for source in &robot.sources {
                println!("cargo:rerun-if-changed={}", source.display());
            }
            for warning in &robot.warnings {
                println!("cargo:warning={warning}");
            }
        }
        let Some(dir) = self.c_library else {
            let file = file.unwrap_or_default();
            let outcome = write_file(&file, &robot.code)?;
            return Ok(RobotReport {
                module,
                file,
                robot,
                outcome,
                c_library: None,
            });
        };
        let options = CLibrary {
            dir: dir.clone(),
            prefix: self.c_prefix,
            runtime_path: self.c_runtime_path,
        };
        let naming = Naming {
            module: &module,
            type_name: &ty,
            source: &shown,
            regenerate: &regenerate,
        };
        let (prefix, files) = library_files(&robot, &naming, &options)?;
        // Everything is checked before anything is written.
        if let Some(file) = &file {
            check_file(file, &robot.code)?;
        }
        check_library(&dir, &files)?;
        let module_outcome = match &file {
            Some(file) => Some(write_file(file, &robot.code)?),
            None => None,
        };
        let library = write_library(&dir, prefix, &files)?;
        let (file, outcome) = match (file, module_outcome) {
            (Some(file), Some(outcome)) => (file, outcome),
            _ => {
                let outcome = (library.files.iter().find(|(path, _)| *path == module_file()))
                    .map_or(WriteOutcome::Written, |(_, outcome)| *outcome);
                (dir.join(module_file()), outcome)
            }
        };
        Ok(RobotReport {
            module,
            file,
            robot,
            outcome,
            c_library: Some(library),
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
