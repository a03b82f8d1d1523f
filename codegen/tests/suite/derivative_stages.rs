//! The derivatives of forward dynamics carried in lanes are emitted as two functions: forward
//! dynamics first (scalars only, handing `q̈` and `D`'s factor on), then the tangents at that
//! `q̈` and their solves. Carried one direction at a time, they stay one function.

use crate::emitted_code::emitted;

/// The text of the free function `name`, up to the next item at the top level.
fn function<'a>(code: &'a str, name: &str) -> Option<&'a str> {
    let start = code.find(&format!("\nfn {name}("))? + 1;
    let end = code[start..].find("\n}\n").map_or(code.len(), |e| start + e);
    Some(&code[start..end])
}

fn has_lane_values(body: &str) -> bool {
    body.contains("splat") || body.contains("Lanes as _")
}

#[test]
fn forward_dynamics_comes_first_in_its_derivatives_in_lanes() {
    let code = emitted("robots/arm7.yaml");
    let first = function(&code, "forward_dynamics_derivatives_part0").expect("a first stage");
    let second = function(&code, "forward_dynamics_derivatives_part1").expect("a second stage");
    assert!(function(&code, "forward_dynamics_derivatives_part2").is_none());
    assert!(!has_lane_values(first), "the first stage computes lane values");
    assert!(has_lane_values(second), "the tangents are not in lanes");
    // The first stage hands `q̈` on (seven values, with the factor and what the tangents reuse).
    assert!(
        first.contains("h0: &mut [f64; "),
        "the first stage hands nothing on"
    );
    // It divides by the factor's pivots; the second stage only multiplies by their inverses.
    assert!(first.contains(" / ") && !second.contains(" / "));
}

#[test]
fn derivatives_one_direction_at_a_time_stay_whole() {
    let code = emitted("robots/ur5.yaml");
    assert!(code.contains("fn forward_dynamics_derivatives("));
    assert!(function(&code, "forward_dynamics_derivatives_part0").is_none());
}
