//! Generates the robot the demo runs on. Copy this crate and change `DESCRIPTION`, or set
//! `DYNGEN_ROBOT=/path/to/robot.yaml` (or `.urdf`; absolute, or relative to this crate) when
//! building. The module and type names are fixed (`robot::Robot`), so `src/main.rs` never
//! changes.

const DESCRIPTION: &str = "../../robots/ur5.yaml";

fn main() {
    println!("cargo:rerun-if-env-changed=DYNGEN_ROBOT");
    let description = std::env::var("DYNGEN_ROBOT").unwrap_or_else(|_| DESCRIPTION.to_string());
    dyngen_codegen::Builder::new(description)
        .module_name("robot")
        .type_name("Robot")
        .compile_or_exit();
}
