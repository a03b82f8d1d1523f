//! Loads the description named by `DYNGEN_SWEEP_DESCRIPTION` (a URDF or YAML path) with dyngen's
//! loader and, when it loads, generates it as `robot::Robot` into `OUT_DIR`. What happened is
//! written to `$OUT_DIR/outcome.json` for `src/main.rs` to print: a description that does not
//! load or generate is a result of the sweep, not a build failure. The cfg `sweep_robot` tells
//! `src/main.rs` that there is generated code to compile against. `DYNGEN_SWEEP_MAX_DOF`, when
//! set, stops after loading a model with more moving joints (generated code grows
//! quadratically: a quick sweep can leave the largest robots out and still check they load).

use dyngen_codegen::description::{self, Choices};
use dyngen_codegen::generate::{generate_robot_with, write_file};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-env-changed=DYNGEN_SWEEP_DESCRIPTION");
    println!("cargo:rerun-if-env-changed=DYNGEN_SWEEP_MAX_DOF");
    println!("cargo::rustc-check-cfg=cfg(sweep_robot)");
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let outcome = match std::env::var_os("DYNGEN_SWEEP_DESCRIPTION") {
        None => json!({ "status": "no_description",
                        "message": "set DYNGEN_SWEEP_DESCRIPTION to a URDF or YAML file" }),
        Some(path) => {
            let path = PathBuf::from(path);
            println!("cargo:rerun-if-changed={}", path.display());
            generate(&path, &out_dir)
        }
    };
    if outcome["status"] == "generated" {
        println!("cargo:rustc-cfg=sweep_robot");
    }
    let text = serde_json::to_string_pretty(&outcome).expect("JSON");
    // Plain write: `write_file` only replaces files that carry dyngen's generated-code marker.
    std::fs::write(out_dir.join("outcome.json"), text).expect("write outcome.json");
}

/// The choices for a bare URDF: angles within 1e-9 rad of a quarter turn made exact, as
/// `tools/sweep.py` hands the file to Pinocchio (`exact_quarter_turns`). A YAML description
/// makes its own.
fn choices(path: &Path) -> Choices {
    let urdf = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
    Choices {
        snap_angles: urdf.then_some(1e-9),
        ..Choices::default()
    }
}

/// Load first (so that a loader error is told apart from a generation error), then generate.
fn generate(path: &Path, out_dir: &Path) -> Value {
    let loaded = match description::load_with(path, &choices(path)) {
        Ok(loaded) => loaded,
        Err(e) => return json!({ "status": "load_error", "message": e.to_string() }),
    };
    let model = &loaded.model;
    let mut outcome = json!({
        "status": "loaded",
        "warnings": loaded.warnings,
        "notes": loaded.notes,
        "dof": model.dof(),
        "joint_names": model.joints().iter().map(|j| j.name.as_str()).collect::<Vec<_>>(),
        "end_effector": model.end_effector().name,
    });
    let max_dof = std::env::var("DYNGEN_SWEEP_MAX_DOF")
        .ok()
        .and_then(|v| v.parse::<usize>().ok());
    if let Some(max) = max_dof.filter(|max| model.dof() > *max) {
        outcome["status"] = "not_generated".into();
        outcome["message"] = format!("{} DOF, above DYNGEN_SWEEP_MAX_DOF={max}", model.dof()).into();
        return outcome;
    }
    let shown = path.to_string_lossy().into_owned();
    // Every group: the comparison calls every function, derivatives included, at any size.
    let all = Choices {
        functions: Some(dyngen_codegen::Functions::all()),
        ..choices(path)
    };
    match generate_robot_with(path, &shown, "Robot", "dyngen sweep harness", &all) {
        Ok(robot) => match write_file(&out_dir.join("robot.rs"), &robot.code) {
            Ok(_) => {
                outcome["status"] = "generated".into();
                outcome["base_parameter_count"] = robot.base_parameter_count.into();
                outcome["generation_seconds"] = robot.elapsed.as_secs_f64().into();
            }
            Err(e) => {
                outcome["status"] = "generate_error".into();
                outcome["message"] = e.to_string().into();
            }
        },
        Err(e) => {
            outcome["status"] = "generate_error".into();
            outcome["message"] = e.to_string().into();
        }
    }
    outcome
}
