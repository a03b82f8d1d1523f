//! Each function of the Panda and the Solo-12 called from Rust as a Rust user calls it (the
//! sines and cosines of the state included, the inputs already `SVector`s), timed over a batch
//! of states: the baseline the C++ program sets the C functions against. The generated modules
//! are the C libraries' own (`DYNGEN_BENCH_ROBOTS`/<robot>/src/robot.rs), compiled with the
//! same profile.

use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::prelude::*;
use std::ffi::{c_char, CStr};
use std::hint::black_box;
use std::time::Instant;

#[rustfmt::skip]
#[allow(clippy::all, dead_code, unused_imports)]
mod panda {
    include!(concat!(env!("DYNGEN_BENCH_ROBOTS"), "/panda/src/robot.rs"));
}
#[rustfmt::skip]
#[allow(clippy::all, dead_code, unused_imports)]
mod solo12 {
    include!(concat!(env!("DYNGEN_BENCH_ROBOTS"), "/solo12/src/robot.rs"));
}

/// The states, as a Rust caller holds them.
struct States<const NQ: usize, const NV: usize, const P: usize, const B: usize> {
    q: Vec<SVector<f64, NQ>>,
    qd: Vec<SVector<f64, NV>>,
    v: Vec<SVector<f64, NV>>,
    a: Vec<SVector<f64, NV>>,
    qdd: Vec<SVector<f64, NV>>,
    tau: Vec<SVector<f64, NV>>,
    theta: Vec<SVector<f64, P>>,
    theta_b: Vec<SVector<f64, B>>,
    r: Vec<SVector<f64, NV>>,
}

/// `count` states of `N` entries, state after state, from the caller.
///
/// # Safety
/// `p` points to `count · N` doubles.
unsafe fn vectors<const N: usize>(p: *const f64, count: usize) -> Vec<SVector<f64, N>> {
    // SAFETY: passed on from the caller.
    let all = unsafe { std::slice::from_raw_parts(p, count * N) };
    all.chunks_exact(N).map(SVector::from_column_slice).collect()
}

impl<const NQ: usize, const NV: usize, const P: usize, const B: usize> States<NQ, NV, P, B> {
    /// # Safety
    /// `inputs` holds q, qd, v, a, qdd, tau, θ, θ_b and r, `count` states of each.
    unsafe fn new(inputs: *const *const f64, count: usize) -> Self {
        // SAFETY: passed on from the caller.
        unsafe {
            let input = |k: usize| *inputs.add(k);
            States {
                q: vectors(input(0), count),
                qd: vectors(input(1), count),
                v: vectors(input(2), count),
                a: vectors(input(3), count),
                qdd: vectors(input(4), count),
                tau: vectors(input(5), count),
                theta: vectors(input(6), count),
                theta_b: vectors(input(7), count),
                r: vectors(input(8), count),
            }
        }
    }
}

/// Nanoseconds per state of one pass of `call` over `count` states.
fn time(count: usize, mut call: impl FnMut(usize)) -> f64 {
    let start = Instant::now();
    for k in 0..count {
        call(black_box(k));
    }
    start.elapsed().as_nanos() as f64 / count as f64
}

/// A frame function's name split into its quantity and reference frame.
fn split(function: &str) -> (&str, Option<ReferenceFrame>) {
    for reference in ReferenceFrame::ALL {
        if let Some(q) = function.strip_suffix(&format!("_{}", reference.keyword())) {
            if q.starts_with("frame_") {
                return (q, Some(reference));
            }
        }
    }
    (function, None)
}

fn panda(function: &str, frame: usize, s: &States<7, 7, 70, 43>) -> Option<f64> {
    use panda::{Frame, Panda as R};
    let f = *Frame::ALL.get(frame)?;
    let (quantity, reference) = split(function);
    let rf = reference.unwrap_or(ReferenceFrame::LocalWorldAligned);
    let n = s.q.len();
    macro_rules! each {
        (|$t:ident, $k:ident| $call:expr) => {
            Some(time(n, |$k| {
                let $t = JointTrig::new(&s.q[$k]);
                black_box($call);
            }))
        };
    }
    match quantity {
        "forward_kinematics" => each!(|t, k| R::forward_kinematics(&t)),
        "jacobian" => each!(|t, k| R::jacobian(&t)),
        "jacobian_dot" => each!(|t, k| R::jacobian_dot(&t, &s.qd[k])),
        "mass_matrix" => each!(|t, k| R::mass_matrix(&t)),
        "coriolis_matrix" => each!(|t, k| R::coriolis_matrix(&t, &s.qd[k])),
        "gravity" => each!(|t, k| R::gravity(&t)),
        "inverse_dynamics" => each!(|t, k| R::inverse_dynamics(&t, &s.qd[k], &s.qdd[k])),
        "slotine_li" => each!(|t, k| R::slotine_li(&t, &s.qd[k], &s.v[k], &s.a[k])),
        "regressor" => each!(|t, k| R::regressor(&t, &s.qd[k], &s.v[k], &s.a[k])),
        "base_regressor" => each!(|t, k| R::base_regressor(&t, &s.qd[k], &s.v[k], &s.a[k])),
        "forward_dynamics" => each!(|t, k| R::forward_dynamics(&t, &s.qd[k], &s.tau[k])),
        "mass_matrix_inverse" => each!(|t, k| R::mass_matrix_inverse(&t)),
        "inverse_dynamics_derivatives" => each!(|t, k| R::inverse_dynamics_derivatives(&t, &s.qd[k], &s.qdd[k])),
        "forward_dynamics_derivatives" => each!(|t, k| R::forward_dynamics_derivatives(&t, &s.qd[k], &s.tau[k])),
        "torque_regressor" => each!(|t, k| R::torque_regressor(&t, &s.qd[k], &s.qdd[k])),
        "base_torque_regressor" => each!(|t, k| R::base_torque_regressor(&t, &s.qd[k], &s.qdd[k])),
        "kinematics" => each!(|t, k| R::kinematics(&t, &s.qd[k])),
        "regressor_products" => {
            each!(|t, k| R::regressor_products(&t, &s.qd[k], &s.v[k], &s.a[k], &s.theta[k], &s.r[k]))
        }
        "base_regressor_products" => {
            each!(|t, k| R::base_regressor_products(&t, &s.qd[k], &s.v[k], &s.a[k], &s.theta_b[k], &s.r[k]))
        }
        "frame_pose" => each!(|t, k| R::frame_pose(f, &t)),
        "frame_jacobian" => each!(|t, k| R::frame_jacobian(f, rf, &t)),
        "frame_jacobian_time_variation" => each!(|t, k| R::frame_jacobian_time_variation(f, rf, &t, &s.qd[k])),
        "frame_velocity" => each!(|t, k| R::frame_velocity(f, rf, &t, &s.qd[k])),
        "frame_classical_acceleration" => {
            each!(|t, k| R::frame_classical_acceleration(f, rf, &t, &s.qd[k], &s.qdd[k]))
        }
        "frame_kinematics" => each!(|t, k| R::frame_kinematics(f, &t, &s.qd[k])),
        _ => None,
    }
}

fn solo12(function: &str, frame: usize, s: &States<19, 18, 130, 94>) -> Option<f64> {
    use solo12::{Frame, Solo12 as R};
    let f = *Frame::ALL.get(frame)?;
    let (quantity, reference) = split(function);
    let rf = reference.unwrap_or(ReferenceFrame::LocalWorldAligned);
    let n = s.q.len();
    macro_rules! each {
        (|$t:ident, $k:ident| $call:expr) => {
            Some(time(n, |$k| {
                let Ok($t) = FloatingTrig::from_configuration(s.q[$k].as_slice()) else {
                    return;
                };
                black_box($call);
            }))
        };
    }
    match quantity {
        "mass_matrix" => each!(|t, k| R::mass_matrix(&t)),
        "coriolis_matrix" => each!(|t, k| R::coriolis_matrix(&t, &s.qd[k])),
        "gravity" => each!(|t, k| R::gravity(&t)),
        "inverse_dynamics" => each!(|t, k| R::inverse_dynamics(&t, &s.qd[k], &s.qdd[k])),
        "slotine_li" => each!(|t, k| R::slotine_li(&t, &s.qd[k], &s.v[k], &s.a[k])),
        "regressor" => each!(|t, k| R::regressor(&t, &s.qd[k], &s.v[k], &s.a[k])),
        "base_regressor" => each!(|t, k| R::base_regressor(&t, &s.qd[k], &s.v[k], &s.a[k])),
        "torque_regressor" => each!(|t, k| R::torque_regressor(&t, &s.qd[k], &s.qdd[k])),
        "base_torque_regressor" => each!(|t, k| R::base_torque_regressor(&t, &s.qd[k], &s.qdd[k])),
        "forward_dynamics" => each!(|t, k| R::forward_dynamics(&t, &s.qd[k], &s.tau[k])),
        "mass_matrix_inverse" => each!(|t, k| R::mass_matrix_inverse(&t)),
        "center_of_mass" => each!(|t, k| R::center_of_mass(&t)),
        "centroidal_momentum_matrix" => each!(|t, k| R::centroidal_momentum_matrix(&t)),
        "centroidal_bias" => each!(|t, k| R::centroidal_bias(&t, &s.qd[k])),
        "inverse_dynamics_derivatives" => each!(|t, k| R::inverse_dynamics_derivatives(&t, &s.qd[k], &s.qdd[k])),
        "forward_dynamics_derivatives" => each!(|t, k| R::forward_dynamics_derivatives(&t, &s.qd[k], &s.tau[k])),
        "frame_pose" => each!(|t, k| R::frame_pose(f, &t)),
        "frame_jacobian" => each!(|t, k| R::frame_jacobian(f, rf, &t)),
        "frame_jacobian_time_variation" => each!(|t, k| R::frame_jacobian_time_variation(f, rf, &t, &s.qd[k])),
        "frame_velocity" => each!(|t, k| R::frame_velocity(f, rf, &t, &s.qd[k])),
        "frame_classical_acceleration" => {
            each!(|t, k| R::frame_classical_acceleration(f, rf, &t, &s.qd[k], &s.qdd[k]))
        }
        "frame_kinematics" => each!(|t, k| R::frame_kinematics(f, &t, &s.qd[k])),
        _ => None,
    }
}

/// Nanoseconds per state of one pass of `function` of `robot` over `count` states, called
/// from Rust; NaN for a function this side does not time.
///
/// # Safety
/// `robot` and `function` are NUL-terminated; `inputs` holds q, qd, v, a, qdd, tau, θ, θ_b and
/// r, `count` states of each, in the robot's sizes.
#[no_mangle]
pub unsafe extern "C" fn dyngen_bench_rust(
    robot: *const c_char,
    function: *const c_char,
    frame: usize,
    count: usize,
    inputs: *const *const f64,
) -> f64 {
    // SAFETY: the caller's contract.
    let (robot, function) = unsafe { (CStr::from_ptr(robot), CStr::from_ptr(function)) };
    let (robot, function) = (robot.to_str().unwrap_or(""), function.to_str().unwrap_or(""));
    let ns = match robot {
        // SAFETY: the caller's contract.
        "panda" => panda(function, frame, &unsafe { States::new(inputs, count) }),
        "solo12" => solo12(function, frame, &unsafe { States::new(inputs, count) }),
        _ => None,
    };
    ns.unwrap_or(f64::NAN)
}
