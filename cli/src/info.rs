//! `dyngen info`: what generating a description gives, without writing anything: joints,
//! end-effector, parameters, base parameters and the operations of each generated function.

use crate::failure::Failure;
use crate::functions::FunctionsArgs;
use crate::loading::{print_diagnostics, LoadingArgs};
use clap::Args;
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_codegen::generate::{generate_robot_with, module_name, type_name};
use dyngen_codegen::model::JointKind;
use std::path::PathBuf;

/// Print a description's joints, parameters, base parameters and generated operation counts.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The robot description (`.yaml` or `.urdf`).
    description: PathBuf,
    #[command(flatten)]
    loading: LoadingArgs,
    #[command(flatten)]
    functions: FunctionsArgs,
}

pub fn run(args: InfoArgs) -> Result<(), Failure> {
    let module = module_name(&args.description);
    let shown = args.description.display().to_string();
    let robot = generate_robot_with(
        &args.description,
        &shown,
        &type_name(&module),
        "dyngen info",
        &args.functions.choose(args.loading.choices())?,
    )?;
    print_diagnostics(&robot.notes, &robot.warnings);
    let model = &robot.model;
    println!("robot: {} ({shown})", model.name());
    println!("DOF: {}", model.dof());
    if let Some(base) = model.floating_base() {
        println!(
            "floating base: body '{}' (nq = {}, nv = {}: base position and quaternion x y z w, base twist in its own frame, then the joints)",
            base.name,
            model.nq(),
            model.nv()
        );
    }
    println!("joints:");
    for joint in model.joints() {
        let (kind, unit) = match joint.kind {
            JointKind::Revolute => ("revolute", "rad"),
            JointKind::Prismatic => ("prismatic", "m"),
        };
        let limits = match joint.limits {
            Some(l) => format!(
                "[{}, {}] {unit}, velocity {}, effort {}",
                l.lower, l.upper, l.velocity, l.effort
            ),
            None => "no limits".to_owned(),
        };
        println!("  {:<24} {kind:<9} {limits}", joint.name);
    }
    let end_effector = model.end_effector();
    println!(
        "end-effector: '{}' (on the body of joint '{}')",
        end_effector.name,
        model.joints()[model.end_effector_body()].name
    );
    let names = match model.floating_base() {
        Some(_) => FloatingDynamics::parameter_names(model),
        None => model.parameter_names(),
    };
    println!("parameters ({}):", names.len());
    println!("  {}", names.join(", "));
    println!("base parameters ({}):", robot.base_parameter_count);
    for name in &robot.base_parameter_names {
        println!("  {name}");
    }
    println!("functions: {}", robot.functions);
    println!("operations per generated function:");
    print!("{}", robot.op_count_table("  "));
    println!("traced in {:.2} s", robot.elapsed.as_secs_f64());
    Ok(())
}
