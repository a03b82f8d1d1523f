//! The plant on a rigid, frictionless plane: one row per contact, `nᵀ J_v` (the plane's normal
//! times the contact point's linear-velocity rows, base axes), its drift `nᵀ (J̇_v q̇)` (the
//! point's classical acceleration at `q̈ = 0`), solved with the runtime's `solve_contacts`.
//!
//! The contact is unilateral. Each step decides it at its start: closed when the point is on
//! the plane and the solved force pushes (`λ ≥ 0`), open otherwise (the free dynamics; with one
//! row, clamping a pulling `λ` to 0 is the whole complementarity problem). An open step in
//! which the point reaches the plane is cut where it does (found on the step's own RK4
//! solution), the point strikes the plane (`D (q̇⁺ − q̇⁻) = Jᵀ n Λ`, `nᵀ J q̇⁺ = 0`: the
//! runtime's `impulse_dynamics` with no restitution, through `solve_contacts` with zero free
//! acceleration), and the rest of the step goes on from there.
//!
//! Why RK4 and not a semi-implicit step: with the contact decided per step the constrained
//! vector field is smooth inside each step, so RK4 keeps its order, and the rows are solved at
//! the acceleration level, so the point leaves the plane only by RK4's local error (`O(h⁵)`
//! per step), which the Baumgarte terms (`RigidPlane::kp`, `kd`) pull back. A semi-implicit
//! Euler step would drift by `O(h²)` per step and need gains near the step's own rate; and
//! the compliant plane is integrated by the same RK4, so the two surfaces differ by their
//! contact only.

use super::{Plant, PlantError, PlantState};
use crate::sim::rigid_plane::RigidPlane;
use crate::sim::rk4::rk4_step;
use dyngen_runtime::{solve_contacts, ContactError, JointTrig, Parameterization, ProximalSettings};
use nalgebra::{SMatrix, SVector, Vector1, Vector3};

/// How far above the plane (m) the point still counts as on it: far below anything a motion
/// shows, and far above what the held contact drifts (the `rigid_plane_*` tests measure at most
/// 1.3e-12 m and hold it to 1e-10 m).
const ON_PLANE: f64 = 1e-9;

/// Where an open step's crossing of the plane is taken as found (m).
const CROSSING_ACCURACY: f64 = 1e-13;

/// A row shorter than this against the point's whole linear Jacobian is rounding: the point
/// cannot move along the normal (a singular posture), and no force could hold it there.
const SINGULAR_ROW: f64 = 1e-9;

/// Secant iterations to find the crossing, and crossings one step may hold (each is an impact
/// and a restart of the rest of the step).
const CROSSING_ITERATIONS: usize = 12;
const CROSSINGS_PER_STEP: usize = 4;

/// The contact's row at one state.
struct Row<const N: usize> {
    /// `nᵀ J_v` (1 × N).
    jacobian: SMatrix<f64, 1, N>,
    /// `nᵀ (J̇_v q̇)`.
    drift: f64,
    /// `g`, the point's height above the plane (< 0 inside).
    height: f64,
    /// `ġ = nᵀ J_v q̇`.
    rate: f64,
    /// `‖J_v‖`, what the row's length is measured against.
    scale: f64,
}

impl<const N: usize> Row<N> {
    /// The row, refused where the point cannot move along the normal.
    fn solvable(&self) -> Result<&SMatrix<f64, 1, N>, PlantError> {
        if self.jacobian.norm() > SINGULAR_ROW * self.scale {
            Ok(&self.jacobian)
        } else {
            Err(PlantError::SingularContact)
        }
    }
}

impl<Z: Parameterization<N, M>, const N: usize, const M: usize> Plant<Z, N, M> {
    fn row(&self, plane: &RigidPlane, s: &PlantState<N>) -> Result<Row<N>, PlantError> {
        plane.check().map_err(PlantError::RigidPlane)?;
        let t = JointTrig::new(&s.q);
        let (pose, j, jd) = self.frame.kinematics::<Z::Robot>(&t, &s.qd);
        let linear = j.fixed_rows::<3>(0);
        let jacobian = plane.normal.transpose() * linear;
        Ok(Row {
            jacobian,
            scale: linear.norm(),
            drift: plane.normal.dot(&(jd.fixed_rows::<3>(0) * s.qd)),
            height: plane.height(&pose.translation),
            rate: (jacobian * s.qd)[0],
        })
    }

    /// The point held on the plane (the row closed, whatever the sign of its force): `q̈` and
    /// the force `λ` (N) with which the plane pushes the point along `n`.
    fn held(
        &self,
        plane: &RigidPlane,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, f64), PlantError> {
        let row = self.row(plane, s)?;
        let jacobian = row.solvable()?;
        let t = JointTrig::new(&s.q);
        let (free, response) = self.forward_dynamics(&t, &s.qd, tau, Some(&jacobian.transpose()))?;
        // A non-finite row or response would read as a singular posture in the solve.
        if !(response.iter().chain(free.iter()).all(|x| x.is_finite()) && row.drift.is_finite()) {
            return Err(PlantError::NonFinite);
        }
        let rhs = Vector1::new(-row.drift - plane.kp * row.height - plane.kd * row.rate);
        let solved = solve_contacts(
            jacobian,
            &response,
            &free,
            &rhs,
            &ProximalSettings::default(),
            None,
        )
        .map_err(contact_error)?;
        Ok((solved.acceleration, solved.forces[0]))
    }

    /// No contact: the free dynamics.
    fn free(&self, s: &PlantState<N>, tau: &SVector<f64, N>) -> Result<PlantState<N>, PlantError> {
        let qdd = self.forward_dynamics(&JointTrig::new(&s.q), &s.qd, tau, None)?.0;
        Ok(PlantState { q: s.qd, qd: qdd })
    }

    /// `Some((q̈, λ))` when the contact is closed at `s`: the point on the plane and pushed
    /// by it.
    fn closed(
        &self,
        plane: &RigidPlane,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
    ) -> Result<Option<(SVector<f64, N>, f64)>, PlantError> {
        if self.row(plane, s)?.height > ON_PLANE {
            return Ok(None);
        }
        let (qdd, push) = self.held(plane, s, tau)?;
        Ok((push >= 0.0).then_some((qdd, push)))
    }

    /// `q̈` and `F̄` at one state: held while the contact is closed, free otherwise.
    pub(super) fn on_rigid_plane(
        &self,
        plane: &RigidPlane,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, Vector3<f64>), PlantError> {
        Ok(match self.closed(plane, s, tau)? {
            Some((qdd, push)) => (qdd, plane.force_on_environment(push)),
            None => (self.free(s, tau)?.qd, Vector3::zeros()),
        })
    }

    /// The plastic impact at `s` when the point is on the plane and moving into it.
    pub(super) fn strike(
        &self,
        plane: &RigidPlane,
        s: &PlantState<N>,
    ) -> Result<(PlantState<N>, f64), PlantError> {
        let row = self.row(plane, s)?;
        if !(row.height <= ON_PLANE && row.rate < 0.0) {
            return Ok((*s, 0.0));
        }
        let jacobian = row.solvable()?;
        let t = JointTrig::new(&s.q);
        let zero = SVector::<f64, N>::zeros();
        let response = self
            .forward_dynamics(&t, &zero, &zero, Some(&jacobian.transpose()))?
            .1;
        let jump = solve_contacts(
            jacobian,
            &response,
            &zero,
            &Vector1::new(-row.rate),
            &ProximalSettings::default(),
            None,
        )
        .map_err(contact_error)?;
        let after = PlantState {
            q: s.q,
            qd: s.qd + jump.acceleration,
        };
        Ok((after, jump.forces[0]))
    }

    /// One step of length `h` under the held torque `tau`.
    pub(super) fn step_on_rigid_plane(
        &self,
        plane: &RigidPlane,
        start: &PlantState<N>,
        tau: &SVector<f64, N>,
        h: f64,
    ) -> Result<PlantState<N>, PlantError> {
        let held = |x: &PlantState<N>| -> Result<PlantState<N>, PlantError> {
            let qdd = self.held(plane, x, tau)?.0;
            Ok(PlantState { q: x.qd, qd: qdd })
        };
        let open_step = |x: &PlantState<N>, dt: f64| rk4_step(0.0, x, dt, |_, y| self.free(y, tau));
        let mut s = self.strike(plane, start)?.0;
        let mut left = h;
        for crossing in 0..=CROSSINGS_PER_STEP {
            if self.closed(plane, &s, tau)?.is_some() {
                return rk4_step(0.0, &s, left, |_, x| held(x));
            }
            let end = open_step(&s, left)?;
            let (g0, g1) = (self.row(plane, &s)?.height, self.row(plane, &end)?.height);
            // Only a point that starts above the plane crosses it; one that starts on it and is
            // not held is leaving it.
            if g1 >= 0.0 || g0 <= 0.0 || crossing == CROSSINGS_PER_STEP {
                return Ok(end);
            }
            let (fraction, at) = self.crossing(plane, &s, left, (g0, end, g1), open_step)?;
            s = self.strike(plane, &at)?.0;
            left *= 1.0 - fraction;
        }
        Ok(s)
    }

    /// Where an open step from `s` of length `h` to `end` reaches the plane (`g0 > 0 > g1`
    /// the heights at the ends): the fraction of the step and the state there, by regula falsi
    /// (Illinois) on the step's own RK4 solution, smooth in the fraction. Never past the
    /// plane by more than [`CROSSING_ACCURACY`], or else the last point found inside it.
    fn crossing(
        &self,
        plane: &RigidPlane,
        s: &PlantState<N>,
        h: f64,
        (g0, end, g1): (f64, PlantState<N>, f64),
        open_step: impl Fn(&PlantState<N>, f64) -> Result<PlantState<N>, PlantError>,
    ) -> Result<(f64, PlantState<N>), PlantError> {
        let (mut lo, mut g_lo, mut hi, mut g_hi) = (0.0, g0, 1.0, g1);
        let mut inside = (1.0, end);
        let mut last_side = 0.0;
        for _ in 0..CROSSING_ITERATIONS {
            let fraction = lo + (hi - lo) * g_lo / (g_lo - g_hi);
            let at = open_step(s, fraction * h)?;
            let g = self.row(plane, &at)?.height;
            if g.abs() <= CROSSING_ACCURACY {
                return Ok((fraction, at));
            }
            if g > 0.0 {
                (lo, g_lo) = (fraction, g);
                if last_side > 0.0 {
                    g_hi *= 0.5;
                }
                last_side = 1.0;
            } else {
                (hi, g_hi) = (fraction, g);
                inside = (fraction, at);
                if last_side < 0.0 {
                    g_lo *= 0.5;
                }
                last_side = -1.0;
            }
        }
        Ok(inside)
    }
}

fn contact_error(e: ContactError) -> PlantError {
    match e {
        ContactError::Redundant { .. } => PlantError::SingularContact,
        other => PlantError::Contact(other),
    }
}
