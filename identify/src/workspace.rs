//! Workspace constraints of an excitation: a frame of the robot kept inside an axis-aligned
//! box or above a plane (a table, a wall), in the base frame, along the whole trajectory.
//!
//! Each region has a margin `m(p)`, positive inside, that is 1-Lipschitz in the frame's
//! position `p`: the signed distance to a plane `(n·p − d)/|n|`, and for a box the smallest of
//! the six distances to its faces' planes. So `|m(p(t)) − m(p(s))| ≤ V |t − s|` whenever the
//! frame moves no faster than `V`.
//!
//! The speed bound `V` holds for every time, not only at samples: `|ṗ| ≤ Σ_j ρ_j |q̇_j|`, with
//! `ρ_j` the largest distance from joint `j`'s axis to the frame that the kinematics allow
//! (the lengths of the joint origins between them and the frame's offset, added; a prismatic
//! joint contributes 1 and its travel) and `|q̇_j| ≤ Σ_l |(a_jl, b_jl)|` for the Fourier
//! series. Loose (every link stretched out at once, every harmonic in phase), but guaranteed.
//!
//! The check ([`Workspace::check`]) evaluates the margin on a grid over one period (the
//! trajectory is periodic: one period is all of it) and certifies each interval `[t_a, t_b]`
//! from its ends: the margin inside is at least `(m_a + m_b − V (t_b − t_a))/2`. An interval
//! that this does not prove non-negative is halved and its midpoint evaluated, until it is
//! proven, a point outside is found, or it is shorter than a millionth of the period (then it
//! counts as a violation). The check is therefore exact, not a sample: a trajectory it accepts
//! stays inside at every instant, and it evaluates densely only where the frame comes close
//! to a boundary.

use crate::fourier::FourierTrajectory;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{JointKind, Model};
use nalgebra::Vector3;
use thiserror::Error;

/// Where a frame must stay, in the base frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Region {
    /// Inside the axis-aligned box `min ≤ p ≤ max` (component-wise).
    Box { min: Vector3<f64>, max: Vector3<f64> },
    /// On the side of the plane the normal points to: `normal·p ≥ offset`.
    Above { normal: Vector3<f64>, offset: f64 },
}

impl Region {
    /// The box from `min` to `max`.
    pub fn between(min: [f64; 3], max: [f64; 3]) -> Region {
        Region::Box {
            min: Vector3::from(min),
            max: Vector3::from(max),
        }
    }

    /// The side of the plane `normal·p = offset` that `normal` points to.
    pub fn above(normal: [f64; 3], offset: f64) -> Region {
        Region::Above {
            normal: Vector3::from(normal),
            offset,
        }
    }

    /// How far inside `p` is (negative outside), 1-Lipschitz in `p`.
    pub fn margin(&self, p: &Vector3<f64>) -> f64 {
        match self {
            Region::Box { min, max } => (0..3)
                .map(|k| (p[k] - min[k]).min(max[k] - p[k]))
                .fold(f64::INFINITY, f64::min),
            Region::Above { normal, offset } => (normal.dot(p) - offset) / normal.norm(),
        }
    }
}

/// A frame of the model (by name; the end-effector's name for the end-effector) and the
/// region it must stay in.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkspaceConstraint {
    pub frame: String,
    pub region: Region,
}

/// Why an excitation with workspace constraints cannot be made.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ExcitationError {
    #[error("the robot has no frame '{frame}'; its frames: {}", available.join(", "))]
    UnknownFrame { frame: String, available: Vec<String> },
    #[error("the box of frame '{frame}' is empty along {axis}: min {min} is not below max {max}")]
    EmptyBox {
        frame: String,
        axis: char,
        min: f64,
        max: f64,
    },
    #[error("the plane of frame '{frame}' has a zero normal")]
    ZeroNormal { frame: String },
    #[error("the region of frame '{frame}' has a number that is not finite")]
    NotFinite { frame: String },
    /// No posture within the joint limits puts every frame strictly inside its region.
    #[error("no excitation satisfies the workspace constraints: {0}")]
    Infeasible(String),
}

/// One constraint resolved against a model.
#[derive(Clone, Debug)]
struct Bound {
    name: String,
    /// The body that carries the frame and the frame's origin in that body's frame.
    body: usize,
    offset: Vector3<f64>,
    region: Region,
    /// `ρ_j` per coordinate (see the module docs).
    reach: Vec<f64>,
}

/// Workspace constraints checked against one model (none by default); see the module docs.
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    bounds: Vec<Bound>,
}

/// The outcome of [`Workspace::check`] on one trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkspaceCheck {
    /// Whether the trajectory stays inside every region at every time (proven, see the module docs).
    pub inside: bool,
    /// The smallest margin (m) at the times evaluated, the time (s) and the frame it is at.
    pub smallest_margin: f64,
    pub time: f64,
    pub frame: String,
    /// A lower bound of the margin over the whole period (m): non-negative when `inside`.
    pub guaranteed_margin: f64,
    /// Times evaluated (grid and refinement).
    pub evaluations: usize,
    /// The speed bound `V` (m/s) the proof used.
    pub speed_bound: f64,
}

/// Intervals shorter than this fraction of the period are not halved again: an interval
/// still unproven there counts as a violation.
const SHORTEST_INTERVAL: f64 = 1e-6;

/// Cap on evaluations of one check: a trajectory that needs more is grazing a boundary over
/// long stretches and counts as a violation. Near a minimum `m₀` of the margin the intervals
/// must shrink to `2m/V`, which takes of the order of `V/√(m₀ · p̈)` evaluations (`p̈` the
/// frame's acceleration away from the boundary): a few thousand for a millimetre.
const MAX_EVALUATIONS: usize = 200_000;

impl Workspace {
    /// The constraints, checked against `model`: each frame exists, each box is non-empty,
    /// each normal non-zero.
    pub fn new(model: &Model, constraints: &[WorkspaceConstraint]) -> Result<Workspace, ExcitationError> {
        let mut bounds = Vec::new();
        for c in constraints {
            let frame = model.frames().iter().find(|f| f.name == c.frame).ok_or_else(|| {
                ExcitationError::UnknownFrame {
                    frame: c.frame.clone(),
                    available: model.frames().iter().map(|f| f.name.clone()).collect(),
                }
            })?;
            let name = c.frame.clone();
            match &c.region {
                Region::Box { min, max } => {
                    if !(min.iter().chain(max.iter()).all(|v| v.is_finite())) {
                        return Err(ExcitationError::NotFinite { frame: name });
                    }
                    if let Some(k) = (0..3).find(|&k| min[k] >= max[k]) {
                        return Err(ExcitationError::EmptyBox {
                            frame: name,
                            axis: ['x', 'y', 'z'][k],
                            min: min[k],
                            max: max[k],
                        });
                    }
                }
                Region::Above { normal, offset } => {
                    if !(normal.iter().all(|v| v.is_finite()) && offset.is_finite()) {
                        return Err(ExcitationError::NotFinite { frame: name });
                    }
                    if normal.norm() == 0.0 {
                        return Err(ExcitationError::ZeroNormal { frame: name });
                    }
                }
            }
            bounds.push(Bound {
                name,
                body: crate::pipeline::carrier(frame),
                offset: frame.placement.translation,
                region: c.region.clone(),
                reach: reach(
                    model,
                    crate::pipeline::carrier(frame),
                    frame.placement.translation.norm(),
                ),
            });
        }
        Ok(Workspace { bounds })
    }

    pub fn is_empty(&self) -> bool {
        self.bounds.is_empty()
    }

    /// The frame of constraint `i`.
    pub(crate) fn frame_name(&self, i: usize) -> &str {
        &self.bounds[i].name
    }

    /// The smallest margin over the constraints at posture `q`, and which constraint it is.
    pub fn margin(&self, dynamics: &NumericDynamics<'_>, q: &[f64]) -> (f64, usize) {
        let poses = dynamics.body_poses(q);
        let mut worst = (f64::INFINITY, 0);
        for (i, b) in self.bounds.iter().enumerate() {
            let (r, p) = &poses[b.body];
            let m = b.region.margin(&(p + r * b.offset));
            if m < worst.0 {
                worst = (m, i);
            }
        }
        worst
    }

    /// A bound on the speed of every constrained frame along `trajectory` (see the module docs).
    pub fn speed_bound(&self, trajectory: &FourierTrajectory) -> f64 {
        let joint_speed: Vec<f64> = (0..trajectory.dof())
            .map(|j| {
                trajectory.a[j]
                    .iter()
                    .zip(&trajectory.b[j])
                    .map(|(a, b)| a.hypot(*b))
                    .sum()
            })
            .collect();
        self.bounds
            .iter()
            .map(|b| b.reach.iter().zip(&joint_speed).map(|(r, v)| r * v).sum::<f64>())
            .fold(0.0, f64::max)
    }

    /// Whether `trajectory` keeps every frame in its region over a whole period, starting from
    /// a grid of `grid` times (see the module docs); with `stop_early` the check ends at the
    /// first time found outside (for a search that needs only the verdict).
    pub fn check(
        &self,
        dynamics: &NumericDynamics<'_>,
        trajectory: &FourierTrajectory,
        grid: usize,
        stop_early: bool,
    ) -> WorkspaceCheck {
        let period = trajectory.period();
        let speed = self.speed_bound(trajectory);
        let grid = grid.max(2);
        let mut out = WorkspaceCheck {
            inside: true,
            smallest_margin: f64::INFINITY,
            time: 0.0,
            frame: String::new(),
            guaranteed_margin: f64::INFINITY,
            evaluations: 0,
            speed_bound: speed,
        };
        if self.is_empty() {
            return out;
        }
        let evaluate = |t: f64, out: &mut WorkspaceCheck| {
            let (m, i) = self.margin(dynamics, &trajectory.at(t).q);
            out.evaluations += 1;
            if m < out.smallest_margin {
                out.smallest_margin = m;
                out.time = t;
                out.frame = self.bounds[i].name.clone();
            }
            if m < 0.0 {
                out.inside = false;
            }
            m
        };
        let h = period / grid as f64;
        let margins: Vec<f64> = (0..grid).map(|k| evaluate(k as f64 * h, &mut out)).collect();
        if !out.inside && stop_early {
            out.guaranteed_margin = out.smallest_margin;
            return out;
        }
        let mut stack: Vec<(f64, f64, f64, f64)> = (0..grid)
            .map(|k| {
                (
                    k as f64 * h,
                    margins[k],
                    (k + 1) as f64 * h,
                    margins[(k + 1) % grid],
                )
            })
            .collect();
        let budget = MAX_EVALUATIONS.max(2 * grid);
        while let Some((ta, ma, tb, mb)) = stack.pop() {
            let bound = 0.5 * (ma + mb - speed * (tb - ta));
            if bound >= 0.0 {
                out.guaranteed_margin = out.guaranteed_margin.min(bound);
                continue;
            }
            if ma < 0.0 || mb < 0.0 {
                // Already known to be outside: halving it would prove nothing more.
                out.guaranteed_margin = out.guaranteed_margin.min(bound);
                continue;
            }
            if tb - ta < SHORTEST_INTERVAL * period || out.evaluations >= budget {
                out.inside = false;
                out.guaranteed_margin = out.guaranteed_margin.min(bound);
                if stop_early {
                    break;
                }
                continue;
            }
            let tm = 0.5 * (ta + tb);
            let mm = evaluate(tm, &mut out);
            if mm < 0.0 {
                out.guaranteed_margin = out.guaranteed_margin.min(mm);
                if stop_early {
                    break;
                }
            }
            stack.push((ta, ma, tm, mm));
            stack.push((tm, mm, tb, mb));
        }
        out.guaranteed_margin = out.guaranteed_margin.min(out.smallest_margin);
        out
    }
}

/// `ρ_j` for the frame at `distance` from the origin of body `body`: per joint on the chain,
/// the lengths between its origin and the frame, added (0 for joints not on the chain); per
/// coordinate, the sum over the joints it drives, times their multipliers.
fn reach(model: &Model, body: usize, distance: f64) -> Vec<f64> {
    let mut reach = vec![0.0; model.dof()];
    let chain = model.chain_to(body);
    // Walking from the frame's body to the base: `below` is the length from the current
    // joint's origin to the frame.
    let mut below = distance;
    for &j in &chain {
        let joint = &model.joints()[j];
        let travel = match (joint.kind, joint.limits) {
            (JointKind::Prismatic, Some(l)) => l.lower.abs().max(l.upper.abs()),
            (JointKind::Prismatic, None) => 1.0,
            (JointKind::Revolute, _) => 0.0,
        };
        below += travel;
        let map = &model.coordinate_maps()[j];
        reach[map.coordinate] += map.multiplier.abs()
            * match joint.kind {
                JointKind::Revolute => below,
                JointKind::Prismatic => 1.0,
            };
        below += joint.origin.translation.norm();
    }
    reach
}
