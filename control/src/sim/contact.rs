//! A compliant plane: `F = k · penetration` along the normal; contact opens and closes.

use nalgebra::Vector3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneContact {
    /// A point of the undeformed surface (base frame).
    pub point: Vector3<f64>,
    /// Unit normal pointing out of the surface (base frame).
    pub normal: Vector3<f64>,
    /// Stiffness `k` (N/m).
    pub stiffness: f64,
}

impl PlaneContact {
    /// A horizontal table at height `z` (normal `+z`).
    pub fn table(z: f64, stiffness: f64) -> Self {
        PlaneContact {
            point: Vector3::new(0.0, 0.0, z),
            normal: Vector3::z(),
            stiffness,
        }
    }

    /// Penetration depth of point `x` (≥ 0 in contact).
    pub fn penetration(&self, x: &Vector3<f64>) -> f64 {
        self.normal.dot(&(self.point - x))
    }

    /// `F̄`: the force the robot's contact point at `x` exerts on the surface (base frame); for
    /// the table `F̄_z = k·min(0, z − z_e)`, negative when pressing.
    pub fn force_on_environment(&self, x: &Vector3<f64>) -> Vector3<f64> {
        let p = self.penetration(x);
        if p > 0.0 {
            -self.normal * (self.stiffness * p)
        } else {
            Vector3::zeros()
        }
    }
}
