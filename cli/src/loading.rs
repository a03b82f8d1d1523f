//! The options every command that reads a description shares: the user's choices
//! ([`Choices`], one flag per key the command line offers), for a bare URDF or the keys a YAML
//! description does not write.

use clap::{Args, ValueEnum};
use dyngen_codegen::description::{Choices, ContactSpec, FrameSelection, FrameSpec, NonPhysicalInertia};
use dyngen_runtime::{ContactKind, ReferenceFrame};

/// Each flag is one key of the description's choices (`docs/descriptions.md`, *Choices*): for a
/// bare URDF, or a key a YAML description does not write (one it writes too is an error).
#[derive(Args, Clone, Debug, Default)]
pub struct LoadingArgs {
    /// `snap_angles`: make origin angles within TOL radians of a quarter turn exact quarter
    /// turns, and axis components that close to 0 exactly 0 (at most 1e-3; each change a
    /// note).
    #[arg(long, value_name = "TOL")]
    pub snap_angles: Option<f64>,
    /// `end_effector`: the link whose pose and Jacobian are generated (default: the leaf at the
    /// end of the longest chain).
    #[arg(long, value_name = "LINK")]
    pub end_effector: Option<String>,
    /// `frames`: a link whose frame is generated besides the end-effector (repeat the option
    /// for more), or `all` for every link that moves.
    #[arg(long = "frame", value_name = "LINK")]
    pub frames: Vec<String>,
    /// `locked_joints`: a joint made rigid at a position (radians, or metres for a prismatic
    /// joint), e.g. `--lock finger_joint1=0.0`; repeat the option for more.
    #[arg(long = "lock", value_name = "JOINT=POSITION", value_parser = locked_joint)]
    pub locked_joints: Vec<(String, f64)>,
    /// `gravity`: the gravity acceleration in the base frame, m/s² (default `0,0,-9.81`).
    #[arg(long, value_name = "X,Y,Z", value_parser = gravity, allow_hyphen_values = true)]
    pub gravity: Option<[f64; 3]>,
    /// `inertia`: what to do with a link whose inertia no real body can have (a negative
    /// principal moment, a broken triangle inequality, mass without extent about an axis):
    /// load it as written with a warning, repair it to the nearest physical inertia (each
    /// change a note), or refuse it.
    #[arg(long, value_enum, value_name = "CHOICE", default_value_t = InertiaArg::AsWritten)]
    pub inertia: InertiaArg,
    /// `floating_base`: the root link flies free (a legged robot, a humanoid): the
    /// configuration gains the base pose and the velocity the base twist.
    #[arg(long)]
    pub floating_base: bool,
    /// `contacts`: a named frame held to the world, `FRAME:point` or `FRAME:frame`, optionally
    /// `:local_world_aligned` (default `local`), e.g. `--contact FL_FOOT:point`; repeat the
    /// option for more. The frame is the end-effector or one of `--frame`.
    #[arg(long = "contact", value_name = "FRAME:KIND[:AXES]", value_parser = contact)]
    pub contacts: Vec<ContactSpec>,
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
    /// The flags as one [`Choices`] value; the keys without a flag here are left at their
    /// default (the commands that generate add theirs: `FunctionsArgs::choose`).
    pub fn choices(&self) -> Choices {
        Choices {
            snap_angles: self.snap_angles,
            end_effector: self.end_effector.as_deref().map(FrameSpec::link),
            frames: match self.frames.iter().any(|f| f == "all") {
                true => FrameSelection::AllLinks,
                false if self.frames.is_empty() => FrameSelection::EndEffector,
                false => FrameSelection::Listed(self.frames.iter().map(FrameSpec::link).collect()),
            },
            locked_joints: self.locked_joints.clone(),
            gravity: self.gravity,
            inertia: self.inertia.into(),
            floating_base: self.floating_base,
            contacts: self.contacts.clone(),
            ..Choices::default()
        }
    }
}

/// `--lock JOINT=POSITION`.
fn locked_joint(text: &str) -> Result<(String, f64), String> {
    let (joint, position) = text
        .split_once('=')
        .ok_or_else(|| format!("expected JOINT=POSITION, found '{text}'"))?;
    let position: f64 = position
        .trim()
        .parse()
        .map_err(|_| format!("the position of joint '{joint}' is not a number: '{position}'"))?;
    match (joint.trim(), position.is_finite()) {
        ("", _) => Err(format!("expected JOINT=POSITION, found '{text}'")),
        (_, false) => Err(format!("the position of joint '{joint}' must be finite")),
        (joint, true) => Ok((joint.to_owned(), position)),
    }
}

/// `--contact FRAME:KIND[:AXES]`.
fn contact(text: &str) -> Result<ContactSpec, String> {
    let parts: Vec<&str> = text.split(':').map(str::trim).collect();
    let kind = match parts.get(1) {
        Some(&"point") => ContactKind::Point,
        Some(&"frame") => ContactKind::Frame,
        Some(other) => return Err(format!("contact kind `{other}`: expected `point` or `frame`")),
        None => return Err(format!("expected FRAME:KIND[:AXES], found '{text}'")),
    };
    let reference = match parts.get(2) {
        None | Some(&"local") => ReferenceFrame::Local,
        Some(&"local_world_aligned") => ReferenceFrame::LocalWorldAligned,
        Some(other) => {
            return Err(format!(
                "contact axes `{other}`: expected `local` or `local_world_aligned`"
            ))
        }
    };
    match (parts[0], parts.len()) {
        ("", _) | (_, 4..) => Err(format!("expected FRAME:KIND[:AXES], found '{text}'")),
        (frame, _) => Ok(ContactSpec {
            frame: frame.to_owned(),
            kind,
            reference,
            to: None,
        }),
    }
}

/// `--gravity X,Y,Z`.
fn gravity(text: &str) -> Result<[f64; 3], String> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("expected three finite numbers X,Y,Z, found '{text}'"))?;
    <[f64; 3]>::try_from(parts).map_err(|_| format!("expected three numbers X,Y,Z, found '{text}'"))
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
