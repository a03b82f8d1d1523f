//! The demo scenario: approach a horizontal table, press with a smooth force ramp, hold, then
//! track a circle on the surface while holding the force; the orientation turns smoothly from
//! the start to the target orientation during the approach and the ramp, then is held (used
//! by tasks with orientation rows).

use crate::controller::{ConfigError, ContactTask, Desired};
use nalgebra::{Matrix3, Rotation3, SVector, Unit, Vector3};

/// Quintic blend `s(u)` on `[0, 1]` with zero first and second derivatives at both ends; returns
/// `(s, s', s'')`.
fn blend(u: f64) -> (f64, f64, f64) {
    if u <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    if u >= 1.0 {
        return (1.0, 0.0, 0.0);
    }
    let (u2, u3) = (u * u, u * u * u);
    (
        u3 * (10.0 - 15.0 * u + 6.0 * u2),
        30.0 * u2 * (1.0 - u) * (1.0 - u),
        60.0 * u * (1.0 - 3.0 * u + 2.0 * u2),
    )
}

/// Phases (durations in s) and geometry of the press-and-circle task, in the task frame (for a
/// table, the base frame with z up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressAndCircle<const N: usize> {
    /// Position of the controlled frame's origin (the end-effector's by default) at the start.
    pub start: Vector3<f64>,
    /// Height of the undeformed surface.
    pub surface: f64,
    /// Surface stiffness `k` of the controller's model (N/m): `F_d = k·(z_e − z_d)`.
    pub stiffness: f64,
    pub approach_time: f64,
    pub ramp_time: f64,
    pub hold_time: f64,
    pub spin_up_time: f64,
    pub circle_time: f64,
    pub radius: f64,
    pub frequency: f64,
    pub target_force: f64,
    /// Null-space posture `q_ν`.
    pub posture: SVector<f64, N>,
    /// Orientation at the start (base frame).
    pub start_orientation: Matrix3<f64>,
    /// The turn from the start to the target orientation, `R_target = Rot(u, φ) R_start`
    /// (base axes), made during the approach and the ramp.
    pub turn_axis: Unit<Vector3<f64>>,
    pub turn_angle: f64,
}

impl<const N: usize> PressAndCircle<N> {
    /// The demo's timing: 1 s approach (skipped when starting in contact), 1 s ramp, 0.5 s hold,
    /// 0.5 s spin-up, then `circle_time` at full speed.
    pub fn new(
        start: Vector3<f64>,
        surface: f64,
        stiffness: f64,
        target_force: f64,
        posture: SVector<f64, N>,
    ) -> Self {
        PressAndCircle {
            start,
            surface,
            stiffness,
            approach_time: if start.z > surface { 1.0 } else { 0.0 },
            ramp_time: 1.0,
            hold_time: 0.5,
            spin_up_time: 0.5,
            circle_time: 8.0,
            radius: 0.05,
            frequency: 0.25,
            target_force,
            posture,
            start_orientation: Matrix3::identity(),
            turn_axis: Vector3::z_axis(),
            turn_angle: 0.0,
        }
    }

    /// Turns from `start` to `target` (rotation matrices, base frame) during the approach and
    /// the ramp (by the shortest rotation), then holds `target`.
    pub fn with_orientation(mut self, start: Matrix3<f64>, target: Matrix3<f64>) -> Self {
        self.start_orientation = start;
        let turn = Rotation3::from_matrix(&(target * start.transpose()));
        (self.turn_axis, self.turn_angle) = turn.axis_angle().unwrap_or((Vector3::z_axis(), 0.0));
        self
    }

    /// The orientation at the end of the turn.
    pub fn target_orientation(&self) -> Matrix3<f64> {
        Rotation3::from_axis_angle(&self.turn_axis, self.turn_angle).into_inner() * self.start_orientation
    }

    /// Duration of the turn (s): the approach and the ramp.
    pub fn turn_time(&self) -> f64 {
        self.approach_time + self.ramp_time
    }

    /// Checks the scenario against the controller's contact model.
    pub fn validate<const T: usize>(&self, task: &ContactTask<T>) -> Result<(), ConfigError> {
        let contra = |s: String| ConfigError::ForceContradictsContact(s);
        if !(self.target_force.is_finite() && self.target_force > 0.0) {
            return Err(contra(format!(
                "a surface can only push: the target force must be > 0 N, got {} N",
                self.target_force
            )));
        }
        if !(self.stiffness.is_finite() && self.stiffness > 0.0) {
            return Err(contra(format!(
                "surface stiffness {} N/m must be > 0",
                self.stiffness
            )));
        }
        // F_t = K (x_t − x_e) must grow when pressing into the surface (−z in the task frame)
        // and must be the measured force on the surface along the same direction.
        let press = Vector3::new(0.0, 0.0, -1.0);
        let dk = (task.stiffness.fixed_columns::<3>(0) * press)[0];
        let ds = (task.force_selection * Vector3::new(0.0, 0.0, -1.0))[0];
        if !(dk > 0.0 && ds > 0.0) {
            return Err(contra(format!(
                "K·(−n) = {dk:.3e} and Σ·(−n) = {ds:.3e}: the controlled force component must be \
                 positive when pressing into the surface (K = [0, 0, −k], Σ = [0, 0, −1])"
            )));
        }
        if (dk - self.stiffness).abs() > 1e-9 * self.stiffness {
            return Err(contra(format!(
                "the desired force assumes k = {} N/m but the controller's K has k = {dk} N/m",
                self.stiffness
            )));
        }
        let times = [
            self.approach_time,
            self.ramp_time,
            self.hold_time,
            self.spin_up_time,
            self.circle_time,
        ];
        if times.iter().any(|t| !(t.is_finite() && *t >= 0.0))
            || !(self.radius.is_finite() && self.radius >= 0.0)
            || !(self.frequency.is_finite() && self.frequency >= 0.0)
        {
            return Err(ConfigError::Invalid {
                name: "scenario",
                detail: "durations, radius and frequency must be finite and ≥ 0".into(),
            });
        }
        Ok(())
    }

    /// Total duration (s).
    pub fn duration(&self) -> f64 {
        self.approach_time + self.ramp_time + self.hold_time + self.spin_up_time + self.circle_time
    }

    /// When the circle starts (s).
    pub fn circle_start(&self) -> f64 {
        self.approach_time + self.ramp_time + self.hold_time
    }

    /// The force at the start of the ramp (> 0 when starting in contact).
    fn initial_force(&self) -> f64 {
        (self.stiffness * (self.surface - self.start.z)).max(0.0)
    }

    /// The desired motion at time `t`, consistent with the contact: `F_d = k (z_e − z_d)`.
    pub fn desired(&self, t: f64) -> Desired<N, 1> {
        let k = self.stiffness;
        // Normal direction: force and height.
        let (f, fd, fdd) = if t < self.approach_time {
            let (s, s1, s2) = blend(t / self.approach_time);
            let h = self.surface - self.start.z; // < 0
            let (z, zd, zdd) = (
                self.start.z + h * s,
                h * s1 / self.approach_time,
                h * s2 / (self.approach_time * self.approach_time),
            );
            (-k * (z - self.surface), -k * zd, -k * zdd)
        } else {
            let f0 = self.initial_force();
            let tau = t - self.approach_time;
            let df = self.target_force - f0;
            if self.ramp_time > 0.0 {
                let (s, s1, s2) = blend(tau / self.ramp_time);
                (
                    f0 + df * s,
                    df * s1 / self.ramp_time,
                    df * s2 / (self.ramp_time * self.ramp_time),
                )
            } else {
                (self.target_force, 0.0, 0.0)
            }
        };
        let (z, zd, zdd) = (self.surface - f / k, -fd / k, -fdd / k);

        // In-plane: a circle through the start point, with a smooth spin-up of the phase.
        let omega = 2.0 * std::f64::consts::PI * self.frequency;
        let tc = (t - self.circle_start()).max(0.0);
        let ts = self.spin_up_time;
        let (phi, phid, phidd) = if tc < ts {
            let u = tc / ts;
            let (s, s1, _) = blend(u);
            // φ = ω ∫ s: ∫₀ᵘ s = u⁴(2.5 − 3u + u²)
            (
                omega * ts * u.powi(4) * (2.5 - 3.0 * u + u * u),
                omega * s,
                omega * s1 / ts,
            )
        } else {
            (omega * (0.5 * ts + (tc - ts)), omega, 0.0)
        };
        let rho = self.radius;
        let (sn, cs) = phi.sin_cos();
        let centre = Vector3::new(self.start.x - rho, self.start.y, 0.0);
        let position = Vector3::new(centre.x + rho * cs, centre.y + rho * sn, z);
        let velocity = Vector3::new(-rho * sn * phid, rho * cs * phid, zd);
        let acceleration = Vector3::new(
            -rho * cs * phid * phid - rho * sn * phidd,
            -rho * sn * phid * phid + rho * cs * phidd,
            zdd,
        );
        // Orientation: Rot(u, φ s) R_start, ω_d = u φ ṡ, ω̇_d = u φ s̈ (a turn about a fixed axis).
        let tt = self.turn_time();
        let (s, s1, s2) = if tt > 0.0 { blend(t / tt) } else { (1.0, 0.0, 0.0) };
        let (s1, s2) = if tt > 0.0 {
            (s1 / tt, s2 / (tt * tt))
        } else {
            (0.0, 0.0)
        };
        let phi = self.turn_angle;
        let orientation =
            Rotation3::from_axis_angle(&self.turn_axis, phi * s).into_inner() * self.start_orientation;
        Desired {
            force: SVector::<f64, 1>::new(f),
            force_dot: SVector::<f64, 1>::new(fd),
            force_ddot: SVector::<f64, 1>::new(fdd),
            position,
            velocity,
            acceleration,
            orientation,
            angular_velocity: self.turn_axis.into_inner() * (phi * s1),
            angular_acceleration: self.turn_axis.into_inner() * (phi * s2),
            posture: self.posture,
            posture_velocity: SVector::zeros(),
            posture_acceleration: SVector::zeros(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The desired trajectory's derivatives are the derivatives of its values (central
    /// differences), in every phase.
    #[test]
    fn derivatives_are_consistent() {
        let start = Rotation3::from_euler_angles(0.3, -0.2, 1.0).into_inner();
        let target = Rotation3::from_euler_angles(3.0, 0.1, 0.4).into_inner();
        let s = PressAndCircle::<2>::new(Vector3::new(0.5, 0.1, 0.3), 0.29, 1e4, 10.0, SVector::zeros())
            .with_orientation(start, target);
        assert!((s.desired(0.0).orientation - start).amax() < 1e-12);
        assert!((s.desired(s.turn_time()).orientation - target).amax() < 1e-12);
        assert!((s.target_orientation() - target).amax() < 1e-12);
        let h = 1e-6;
        let mut t = 0.013;
        while t < s.duration() {
            let (a, b, c) = (s.desired(t - h), s.desired(t), s.desired(t + h));
            let dp = (c.position - a.position) / (2.0 * h);
            let dv = (c.velocity - a.velocity) / (2.0 * h);
            let df = (c.force - a.force) / (2.0 * h);
            let dfd = (c.force_dot - a.force_dot) / (2.0 * h);
            assert!((dp - b.velocity).amax() < 1e-6, "t={t} {dp} {}", b.velocity);
            assert!((dv - b.acceleration).amax() < 1e-5, "t={t}");
            assert!((df - b.force_dot).amax() < 1e-4, "t={t}");
            assert!((dfd - b.force_ddot).amax() < 1e-3, "t={t}");
            assert!((b.force[0] - 1e4 * (0.29 - b.position.z)).abs() < 1e-9);
            // Ṙ_d = [ω_d]× R_d, and ω̇_d is the derivative of ω_d.
            let dr = (c.orientation - a.orientation) / (2.0 * h);
            let w = crate::controller::orientation::skew(&b.angular_velocity) * b.orientation;
            assert!((dr - w).amax() < 1e-6, "t={t}");
            let dw = (c.angular_velocity - a.angular_velocity) / (2.0 * h);
            assert!((dw - b.angular_acceleration).amax() < 1e-5, "t={t}");
            t += 0.0937;
        }
    }
}
