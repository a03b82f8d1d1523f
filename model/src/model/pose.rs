//! Rigid placements of frames ([`Pose`], shared with generated code), built from URDF
//! `origin` (xyz, rpy).

pub use dyngen_runtime::Pose;
use nalgebra::{Matrix3, Vector3};

/// Sine and cosine that are exact (0, ±1) at multiples of π/2.
///
/// URDF files write quarter turns as `1.5707963267948966` or `1.5708`; the floating-point cosine
/// of that is 6e-17, not 0. Exact zeros let the code generator drop whole products, so an angle
/// within 1e-9 rad of a quarter turn is taken as the quarter turn. The change is below the
/// precision with which any real robot is described.
pub fn exact_sin_cos(angle: f64) -> (f64, f64) {
    let quarter = std::f64::consts::FRAC_PI_2;
    let k = (angle / quarter).round();
    if (angle - k * quarter).abs() < 1e-9 && k.abs() < 1e6 {
        match (k as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        angle.sin_cos()
    }
}

/// URDF origin: translation `xyz`, rotation `Rz(yaw) · Ry(pitch) · Rx(roll)` (fixed axes).
pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Pose {
    let (sr, cr) = exact_sin_cos(rpy[0]);
    let (sp, cp) = exact_sin_cos(rpy[1]);
    let (sy, cy) = exact_sin_cos(rpy[2]);
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cr, -sr, 0.0, sr, cr);
    let ry = Matrix3::new(cp, 0.0, sp, 0.0, 1.0, 0.0, -sp, 0.0, cp);
    let rz = Matrix3::new(cy, -sy, 0.0, sy, cy, 0.0, 0.0, 0.0, 1.0);
    Pose {
        rotation: rz * ry * rx,
        translation: Vector3::from(xyz),
    }
}
