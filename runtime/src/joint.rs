//! Per-joint data that generated functions take or publish.

use nalgebra::SVector;

/// Joint positions with their sines and cosines, computed once per control tick and shared by
/// every quantity (they are a large share of the cost of kinematics and gravity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointTrig<const N: usize> {
    pub q: [f64; N],
    pub sin: [f64; N],
    pub cos: [f64; N],
}

impl<const N: usize> JointTrig<N> {
    /// All sines and cosines in one pass over the joints (SIMD lanes where the target has
    /// them): they are most of the cost of kinematics and gravity.
    #[inline(always)]
    pub fn new(q: &SVector<f64, N>) -> Self {
        // The caller's array itself, not a fresh copy: a copy just stored in smaller pieces
        // cannot be forwarded to the kernel's wide loads.
        crate::trig::joint_trig(&q.data.0[0])
    }
}

/// A joint's limits as its description gives them: position (rad or m), speed (rad/s or m/s)
/// and effort (N·m or N). A limit the description does not set is infinite (a continuous
/// joint has no position limits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    pub lower: f64,
    pub upper: f64,
    pub velocity: f64,
    pub effort: f64,
}

impl JointLimits {
    /// No limit at all.
    pub const NONE: JointLimits = JointLimits {
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
        velocity: f64::INFINITY,
        effort: f64::INFINITY,
    };
}
