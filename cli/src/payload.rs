//! `dyngen payload`: a payload (a tool, a grasped object) identified on a robot whose
//! description is known, from joint torques, a wrist force/torque sensor, or both; the
//! description with the payload written.

use crate::failure::Failure;
use crate::identifiable::load_identifiable;
use crate::loading::LoadingArgs;
use clap::{Args, ValueEnum};
use dyngen_identify::{identify_payload, read_csv, PayloadData, PayloadOptions};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum From {
    Torques,
    Wrench,
    Both,
}

/// Identify a payload on a known robot from a data CSV (`time`, `q[<joint>]`, and
/// `tau[<joint>]` and/or a force/torque sensor's `fx`, `fy`, `fz`, `mx`, `my`, `mz[<frame>]`;
/// `qd` and `qdd` optional), and write the description with the payload.
#[derive(Args, Debug)]
pub struct PayloadArgs {
    /// The robot's description, identified or nominal, without the payload (`.yaml` or
    /// `.urdf`): its parameters are held.
    description: PathBuf,
    /// The measured data with the payload attached; `-` reads the standard input.
    data: PathBuf,
    /// The description with the payload welded on: dyngen YAML, or URDF when the name ends in
    /// `.urdf` (then, when URDF cannot say everything, also `<name>.dyngen.yaml` beside it,
    /// which loads the URDF as the robot with the payload).
    #[arg(short, long, value_name = "with_payload.yaml")]
    output: PathBuf,
    /// The frame the payload is attached at and reported in (default: the sensor's frame
    /// with wrench data, else the end-effector).
    #[arg(long, value_name = "FRAME")]
    payload_frame: Option<String>,
    /// What to identify from (default: everything the data has).
    #[arg(long, value_enum)]
    from: Option<From>,
    /// Re-fit the description's joint terms (friction, armature, offset) from the torques
    /// beside the payload.
    #[arg(long)]
    refit_joint_terms: bool,
    /// Cutoff of the low-pass filter used when velocities or accelerations are missing, in Hz.
    #[arg(long, value_name = "HZ", default_value_t = PayloadOptions::default().cutoff)]
    cutoff: f64,
    /// Write the description even when the force/torque sensor's readings fit no payload or
    /// disagree with the joint torques (a flipped or mis-framed sensor).
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    loading: LoadingArgs,
}

pub fn run(args: PayloadArgs) -> Result<(), Failure> {
    let model = load_identifiable(&args.description, &args.loading)?;
    let samples = read_csv(&args.data, &model, false)?;
    let options = PayloadOptions {
        frame: args.payload_frame,
        data: args.from.map(|f| match f {
            From::Torques => PayloadData::Torques,
            From::Wrench => PayloadData::Wrench,
            From::Both => PayloadData::Both,
        }),
        refit_joint_terms: args.refit_joint_terms,
        cutoff: args.cutoff,
    };
    let p = identify_payload(&model, &samples, &options)?;
    let fit = &p.least_squares;
    println!(
        "{}: payload at frame '{}' from {:?}, {} samples used{}",
        model.name(),
        p.frame,
        p.data,
        p.samples_used,
        if p.differentiated {
            " (q̇, q̈ by filter and differences)"
        } else {
            ""
        }
    );
    println!("mass {:.6} kg (σ {:.2e})", p.mass, fit.std_dev[0]);
    println!(
        "centre of mass [{:.6}, {:.6}, {:.6}] m in '{}'",
        p.com.x, p.com.y, p.com.z, p.frame
    );
    let i = &p.inertia_com;
    println!(
        "inertia about the centre of mass (xx, xy, yy, xz, yz, zz) [{:.4e}, {:.4e}, {:.4e}, {:.4e}, {:.4e}, {:.4e}] kg·m²",
        i[(0, 0)],
        i[(0, 1)],
        i[(1, 1)],
        i[(0, 2)],
        i[(1, 2)],
        i[(2, 2)]
    );
    if p.made_consistent {
        println!("(the least squares were not a physical body: this is the nearest that is)");
    }
    println!("{:>14} {:>14}  least squares", "estimate", "σ");
    for k in 0..fit.theta_b.len() {
        println!(
            "{:>14.6e} {:>14.3e}  {}",
            fit.theta_b[k], fit.std_dev[k], fit.names[k]
        );
    }
    if let Some(offset) = p.sensor_offset {
        println!("sensor offset [fx, fy, fz, mx, my, mz]: {offset:.4?}");
    }
    println!("noise per channel (σ, from the weighted residuals):");
    let mut channels: Vec<String> = Vec::new();
    if matches!(p.data, PayloadData::Torques | PayloadData::Both) {
        channels.extend(model.joints().iter().map(|j| format!("tau[{}]", j.name)));
    }
    if matches!(p.data, PayloadData::Wrench | PayloadData::Both) {
        channels.extend(["fx", "fy", "fz", "mx", "my", "mz"].iter().map(|c| c.to_string()));
    }
    for (name, sigma) in channels.iter().zip(&fit.joint_noise) {
        println!("  {name}: σ = {sigma:.4e}");
    }
    if let Some(check) = &p.sources {
        if let Some(misfit) = check.sensor_misfit {
            println!("sensor residuals over the noise their scatter shows (fx … mz): {misfit:.2?}");
        }
        if !check.joint_cost.is_empty() {
            println!(
                "noise fitted together over fitted alone, per channel: {:.2?}",
                check.joint_cost
            );
        }
    }
    for note in &p.notes {
        eprintln!("note: {note}");
    }
    let data = crate::identify::data_name(&args.data);
    let disagreement = p.sources.as_ref().and_then(|s| s.disagreement.as_ref());
    for warning in p.warnings.iter().filter(|w| Some(*w) != disagreement) {
        eprintln!("warning: {data}: {warning}");
    }
    if let Some(why) = disagreement {
        if !args.force {
            return Err(Failure::from(format!(
                "{data}: {why}; nothing written (--force writes it anyway)"
            )));
        }
        eprintln!("warning: {data}: {why}; written anyway (--force)");
    }
    crate::identify::write_description(
        &p.model,
        &args.output,
        &args.description,
        || p.urdf(&data, &args.output),
        || p.written(&data, &args.output),
    )
}
