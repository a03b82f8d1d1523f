//! Rigid placements of frames ([`Pose`], shared with generated code), built from URDF
//! `origin` (xyz, rpy).

pub use dyngen_runtime::Pose;
use nalgebra::{Matrix3, Vector3};

/// The number of quarter turns `angle` is, when it is one to the precision of `f64`: within
/// one unit in the last place of `k·π/2`, as `1.5707963267948966`, `-3.141592653589793` or
/// `std::f64::consts::FRAC_PI_2` write them (and exactly 0 for no turn). `None` for any other
/// angle, however close: `1.5708` and `1.57079632679` are used as written (making them exact is
/// the description's choice, `snap_angles`, and each change a note).
pub fn quarter_turns(angle: f64) -> Option<i64> {
    let quarter = std::f64::consts::FRAC_PI_2;
    let k = (angle / quarter).round();
    let exact = (angle - k * quarter).abs() <= f64::EPSILON * angle.abs();
    (exact && k.abs() < 1e6).then_some(k as i64)
}

/// Sine and cosine that are exact (0, ±1) at multiples of π/2 ([`quarter_turns`]).
///
/// The floating-point cosine of `1.5707963267948966` (π/2 to the last bit) is 6e-17, not 0.
/// Exact zeros let the code generator drop whole products; any other angle gets
/// [`f64::sin_cos`].
pub fn exact_sin_cos(angle: f64) -> (f64, f64) {
    match quarter_turns(angle).map(|k| k.rem_euclid(4)) {
        Some(0) => (0.0, 1.0),
        Some(1) => (1.0, 0.0),
        Some(2) => (0.0, -1.0),
        Some(_) => (-1.0, 0.0),
        None => angle.sin_cos(),
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
