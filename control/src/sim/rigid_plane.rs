//! A rigid, frictionless plane: the contact point may touch it but never enter it. While the
//! point is on it, one row holds it there (the normal component of the point's velocity); the
//! force of that row is whatever the motion and the torques need, never a pull.

use nalgebra::Vector3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidPlane {
    /// A point of the surface (base frame).
    pub point: Vector3<f64>,
    /// Unit normal pointing out of the surface (base frame).
    pub normal: Vector3<f64>,
    /// Baumgarte stabilisation, `K_p` (1/s²) and `K_d` (1/s): in contact the row asks for
    /// `g̈ = −K_p g − K_d ġ` (`g` the point's height above the plane) instead of `g̈ = 0`, which
    /// pulls back what the integration lets drift.
    pub kp: f64,
    pub kd: f64,
}

impl RigidPlane {
    /// `K_p = ω²`, `K_d = 2ω` with `ω = 100 rad/s`: critically damped, a drift decays by `e`
    /// in about 10 ms (ten control periods), and `ω h = 0.02` at the plant's 5 kHz, far inside
    /// what RK4 integrates accurately.
    pub const KP: f64 = 1e4;
    pub const KD: f64 = 200.0;

    /// A horizontal table at height `z` (normal `+z`), with the default gains.
    pub fn table(z: f64) -> Self {
        RigidPlane {
            point: Vector3::new(0.0, 0.0, z),
            normal: Vector3::z(),
            kp: Self::KP,
            kd: Self::KD,
        }
    }

    /// The height `g` of point `x` above the plane (< 0 inside).
    pub fn height(&self, x: &Vector3<f64>) -> f64 {
        self.normal.dot(&(x - self.point))
    }

    /// `F̄`: the force the robot's contact point exerts on the plane (base frame) when the plane
    /// pushes it out with `push` (N, ≥ 0 in contact); for the table `F̄_z = −push`, negative
    /// when pressing, as for [`super::PlaneContact::force_on_environment`].
    pub fn force_on_environment(&self, push: f64) -> Vector3<f64> {
        -self.normal * push
    }

    /// Why the plane cannot be simulated, if it cannot: a normal that is not a unit vector
    /// (the row's force would not be the force in newtons), gains that are negative or not
    /// finite.
    pub fn check(&self) -> Result<(), &'static str> {
        if !self.point.iter().all(|x| x.is_finite()) {
            return Err("the rigid plane's point must be finite");
        }
        let off_unit = (self.normal.norm() - 1.0).abs();
        if off_unit.is_nan() || off_unit > 1e-9 {
            return Err("the rigid plane's normal must be a unit vector");
        }
        if !(self.kp.is_finite() && self.kd.is_finite() && self.kp >= 0.0 && self.kd >= 0.0) {
            return Err("the rigid plane's Baumgarte gains must be finite and ≥ 0");
        }
        Ok(())
    }
}
