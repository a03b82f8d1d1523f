//! The generic dynamics of a description at states read from standard input, for a script that
//! compares dyngen with another library (`tools/identified_urdf_check.py`).
//!
//! ```text
//! cargo run -p dyngen-model --example dynamics_at_states -- DESCRIPTION < states.txt
//! ```
//!
//! Prints `joints <name>…` (the order of every vector below), `columns <kind>…` (the
//! joint-parameter columns chosen: armature, viscous, coulomb, offset), `smoothing <ε>` or
//! `smoothing none`, then per joint `terms <name> <armature> <viscous> <coulomb> <offset>`,
//! each the value the model uses (0 for a column the description does not choose). Then, for
//! each input line `q… q̇… q̈…` (the joints' values, in that order), `tau …` (inverse
//! dynamics, joint terms included) and `mass …` (the mass matrix row by row, armature
//! included). Values are printed with 17 significant digits; a bad description or line is one
//! error on standard error and exit status 1.

use dyngen_model::description::load;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::JointTermKind;
use std::io::BufRead;
use std::path::Path;
use std::process::ExitCode;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn line(label: &str, values: impl IntoIterator<Item = f64>) -> String {
    let values: Vec<String> = values.into_iter().map(|v| format!("{v:.17e}")).collect();
    format!("{label} {}", values.join(" "))
}

fn run() -> Result<(), String> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: dynamics_at_states DESCRIPTION < states.txt")?;
    let model = load(Path::new(&path)).map_err(|e| e.to_string())?.model;
    let n = model.dof();
    let names: Vec<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
    println!("joints {}", names.join(" "));
    let terms = model.joint_terms();
    let kinds: Vec<&str> = terms
        .kinds
        .iter()
        .map(|k| match k {
            JointTermKind::Armature => "armature",
            JointTermKind::Viscous => "viscous",
            JointTermKind::Coulomb => "coulomb",
            JointTermKind::Offset => "offset",
        })
        .collect();
    println!("columns {}", kinds.join(" "));
    match terms.coulomb_smoothing {
        Some(e) => println!("smoothing {e:.17e}"),
        None => println!("smoothing none"),
    }
    let chosen = |kind: JointTermKind, v: f64| if terms.kinds.contains(&kind) { v } else { 0.0 };
    for (name, v) in names
        .iter()
        .zip(model.joint_term_values_from(&model.parameters()))
    {
        println!(
            "{}",
            line(
                &format!("terms {name}"),
                [
                    chosen(JointTermKind::Armature, v.armature),
                    chosen(JointTermKind::Viscous, v.viscous),
                    chosen(JointTermKind::Coulomb, v.coulomb),
                    chosen(JointTermKind::Offset, v.offset),
                ]
            )
        );
    }
    let dynamics = NumericDynamics::new(&model);
    for (number, text) in std::io::stdin().lock().lines().enumerate() {
        let text = text.map_err(|e| format!("standard input: {e}"))?;
        if text.trim().is_empty() {
            continue;
        }
        let state = text
            .split_whitespace()
            .map(|v| {
                v.parse::<f64>()
                    .map_err(|e| format!("line {}: '{v}': {e}", number + 1))
            })
            .collect::<Result<Vec<f64>, String>>()?;
        if state.len() != 3 * n {
            return Err(format!(
                "line {}: {} values, expected {} (q, q̇, q̈ of {n} joints)",
                number + 1,
                state.len(),
                3 * n
            ));
        }
        let (q, qd, qdd) = (&state[..n], &state[n..2 * n], &state[2 * n..]);
        println!(
            "{}",
            line("tau", dynamics.inverse_dynamics(q, qd, qdd).iter().copied())
        );
        let mass = dynamics.mass_matrix(q);
        println!("{}", line("mass", (0..n * n).map(|k| mass[(k / n, k % n)])));
    }
    Ok(())
}
