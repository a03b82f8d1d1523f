//! The sweep harness's program (see `Cargo.toml`).
//!
//! `dyngen-sweep-harness outcome` prints what the build script recorded (loaded or not, the
//! message, warnings, notes, DOF, joint names, end-effector); `dyngen-sweep-harness compare
//! REF.json` evaluates the compiled generated code at every state of a reference file written
//! by `tools/sweep.py` (the fields of `codegen/tests/fixtures/README.md`) and prints, as one
//! JSON object, the largest relative error per quantity over the states.

#[cfg(sweep_robot)]
mod compare;
#[cfg(sweep_robot)]
dyngen_runtime::include_robot!(robot);

const OUTCOME: &str = include_str!(concat!(env!("OUT_DIR"), "/outcome.json"));

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
        ["outcome"] => println!("{OUTCOME}"),
        ["compare", reference] => compare_with(reference),
        _ => {
            eprintln!("usage: dyngen-sweep-harness outcome | compare REFERENCE.json");
            std::process::exit(2);
        }
    }
}

#[cfg(sweep_robot)]
fn compare_with(reference: &str) {
    // Generated functions of large robots keep many temporaries on the stack.
    let reference = reference.to_owned();
    let worker = std::thread::Builder::new()
        .stack_size(512 << 20)
        .spawn(move || compare::run(&reference))
        .expect("spawn the comparison thread");
    match worker.join().expect("the comparison panicked") {
        Ok(result) => println!("{result}"),
        Err(message) => {
            println!("{}", serde_json::json!({ "error": message }));
            std::process::exit(1);
        }
    }
}

#[cfg(not(sweep_robot))]
fn compare_with(_: &str) {
    eprintln!("no generated robot to compare (see `dyngen-sweep-harness outcome`)");
    std::process::exit(1);
}
