//! The options every command that reads a description shares: the choices a YAML wrapper
//! would make for a bare URDF file.

use clap::{Args, ValueEnum};
use dyngen_codegen::description::{FrameSelection, FrameSpec, NonPhysicalInertia, UrdfOptions};

#[derive(Args, Clone, Debug, Default)]
pub struct LoadingArgs {
    /// For a bare URDF: make origin angles within TOL radians of a quarter turn exact quarter
    /// turns, and axis components that close to 0 exactly 0 (at most 1e-3; each change is a
    /// warning). A YAML description sets `snap_angles:` itself.
    #[arg(long, value_name = "TOL")]
    pub snap_angles: Option<f64>,
    /// For a bare URDF: the link whose pose and Jacobian are generated (default: the leaf at
    /// the end of the longest chain). A YAML description sets `end_effector:` itself.
    #[arg(long, value_name = "LINK")]
    pub end_effector: Option<String>,
    /// For a bare URDF: a link whose frame is generated besides the end-effector (repeat the
    /// option for more), or `all` for every link that moves. A YAML description sets
    /// `frames:` itself.
    #[arg(long = "frame", value_name = "LINK")]
    pub frames: Vec<String>,
    /// For a bare URDF: what to do with a link whose inertia no real body can have (a negative
    /// principal moment, a broken triangle inequality, mass without extent about an axis):
    /// load it as written with a warning, repair it to the nearest physical inertia (each
    /// change a note), or refuse it. A YAML description sets `inertia:` itself.
    #[arg(long, value_enum, value_name = "CHOICE", default_value_t = InertiaArg::AsWritten)]
    pub inertia: InertiaArg,
    /// For a bare URDF: the root link flies free (a legged robot, a humanoid): the
    /// configuration gains the base pose and the velocity the base twist. A YAML description
    /// sets `floating_base:` itself.
    #[arg(long)]
    pub floating_base: bool,
}

/// `--inertia`: [`NonPhysicalInertia`] as the command line spells it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum InertiaArg {
    #[default]
    AsWritten,
    Repair,
    Strict,
}

impl From<InertiaArg> for NonPhysicalInertia {
    fn from(arg: InertiaArg) -> Self {
        match arg {
            InertiaArg::AsWritten => NonPhysicalInertia::AsWritten,
            InertiaArg::Repair => NonPhysicalInertia::Repair,
            InertiaArg::Strict => NonPhysicalInertia::Strict,
        }
    }
}

impl LoadingArgs {
    pub fn urdf_options(&self) -> UrdfOptions {
        UrdfOptions {
            snap_angles: self.snap_angles,
            end_effector: self.end_effector.as_ref().map(|link| FrameSpec {
                name: None,
                link: link.clone(),
                xyz: [0.0; 3],
                rpy: [0.0; 3],
            }),
            frames: match self.frames.iter().any(|f| f == "all") {
                true => FrameSelection::AllLinks,
                false if self.frames.is_empty() => FrameSelection::EndEffector,
                false => FrameSelection::Listed(self.frames.iter().map(FrameSpec::link).collect()),
            },
            inertia: self.inertia.into(),
            floating_base: self.floating_base,
            ..UrdfOptions::default()
        }
    }
}

/// Prints what loading a description said: its notes, then its warnings, one line each on
/// stderr (stdout stays the command's output).
pub fn print_diagnostics(notes: &[String], warnings: &[String]) {
    for note in notes {
        eprintln!("note: {note}");
    }
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
}
