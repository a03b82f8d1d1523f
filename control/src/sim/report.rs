//! What a demo run prints and writes: the summary table (Markdown) and one CSV per run.
//! Shared by the `hybrid_force` example and the template crate for a user's own robot.

use super::demo::RunKind;
use super::run::{RunResult, RunStatus, Sample};
use std::fmt::Write as _;
use std::path::Path;

/// The summary over `t ≥ from` of each run as a Markdown table; with an orientation column
/// when `oriented` (task dimension 5 or 6).
pub fn summary_table(results: &[(RunKind, RunResult)], from: f64, oriented: bool) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| run | RMS force error (N) | RMS in-plane error (mm) |{} final null-space error (rad) | max abs(τ) (N·m) | control tick (µs, median) | status |",
        if oriented { " RMS orientation error (mrad) |" } else { "" }
    );
    let _ = writeln!(
        out,
        "|---|---|---|{}---|---|---|---|",
        if oriented { "---|" } else { "" }
    );
    // No sample in the window (a run that diverged before it): say so rather than NaN.
    let sci = |v: f64| {
        if v.is_finite() {
            format!("{v:.3e}")
        } else {
            "—".to_string()
        }
    };
    for (kind, res) in results {
        let s = res.summary(from);
        let _ = writeln!(
            out,
            "| {} | {} | {} |{} {:.3e} | {:.1} | {:.2} | {} |",
            kind.label(),
            sci(s.rms_force_error),
            sci(s.rms_in_plane_error * 1e3),
            if oriented {
                format!(" {} |", sci(s.rms_orientation_error * 1e3))
            } else {
                String::new()
            },
            s.final_null_error,
            s.max_tau,
            s.median_tick_ns / 1e3,
            match &res.status {
                RunStatus::Completed => "completed".to_string(),
                RunStatus::Diverged { time, .. } => format!("diverged at {time:.3} s"),
            }
        );
    }
    out
}

/// One row per control tick (SI units; the orientation error is `NaN` for the position task).
pub fn write_csv(path: &Path, samples: &[Sample]) -> std::io::Result<()> {
    let mut s = String::from(
        "t,force,true_force,desired_force,force_error,in_plane_error_m,orientation_error_rad,null_error,lyapunov,theta_error,joint_term_error,prediction_error,tau_max,tick_ns,damping,stiffness,penetration_m\n",
    );
    for x in samples {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            x.t,
            x.force,
            x.true_force,
            x.desired_force,
            x.force_error,
            x.in_plane_error,
            x.orientation_error,
            x.null_error,
            x.lyapunov,
            x.theta_error,
            x.joint_term_error,
            x.prediction_error,
            x.tau_max,
            x.tick_ns,
            x.damping,
            x.stiffness,
            x.penetration
        );
    }
    std::fs::write(path, s)
}
