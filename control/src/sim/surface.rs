//! What the simulated robot touches: a compliant plane (the default) or a rigid one.

use super::contact::PlaneContact;
use super::rigid_plane::RigidPlane;
use nalgebra::Vector3;

/// The plant's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// `F = k · penetration` along the normal: the force is a function of the position.
    Compliant(PlaneContact),
    /// Never entered: the force holds the point on the plane, opens when it would pull, and
    /// the point strikes the plane (a velocity jump) when it reaches it.
    Rigid(RigidPlane),
}

impl Surface {
    /// A point of the (undeformed) surface, base frame.
    pub fn point(&self) -> Vector3<f64> {
        match self {
            Surface::Compliant(c) => c.point,
            Surface::Rigid(r) => r.point,
        }
    }

    /// Unit normal pointing out of the surface, base frame.
    pub fn normal(&self) -> Vector3<f64> {
        match self {
            Surface::Compliant(c) => c.normal,
            Surface::Rigid(r) => r.normal,
        }
    }

    /// Penetration depth of point `x` below the (undeformed) surface (> 0 inside).
    pub fn penetration(&self, x: &Vector3<f64>) -> f64 {
        match self {
            Surface::Compliant(c) => c.penetration(x),
            Surface::Rigid(r) => -r.height(x),
        }
    }
}

impl From<PlaneContact> for Surface {
    fn from(c: PlaneContact) -> Self {
        Surface::Compliant(c)
    }
}

impl From<RigidPlane> for Surface {
    fn from(r: RigidPlane) -> Self {
        Surface::Rigid(r)
    }
}

/// Which surface the demo's table is ([`super::DemoOptions::surface`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SurfaceKind {
    /// A [`PlaneContact`] of stiffness [`super::DemoOptions::stiffness`], which the
    /// controller's contact model has exactly.
    #[default]
    Compliant,
    /// A [`RigidPlane`] with the default Baumgarte gains. The controller still models a
    /// compliant surface of stiffness [`super::DemoOptions::stiffness`], its undeformed surface
    /// `target_force / stiffness` above the plane: exact at the target force, and in contact
    /// (the measured force in use) whenever the point is on the plane.
    Rigid,
}
