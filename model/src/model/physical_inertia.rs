//! How far a rigid body's inertia is from one a real body can have, and the nearest one that is.
//!
//! A rotational inertia about the centre of mass belongs to a real mass distribution when its
//! principal moments `I1 ≤ I2 ≤ I3` satisfy the triangle inequality `I1 + I2 ≥ I3` (which
//! implies `I1 ≥ 0`): equivalently, when the second moments of the mass, `Σ = ½ tr(I)·1 − I`,
//! are positive semi-definite (the pseudo-inertia's rotational block). Vendor files break this
//! by rounding, by a sign slip, or by a CAD export; the dynamics (`D`, `g`, `J`, `τ`) are still
//! well defined, only a parameter estimate that must stay physical needs a physical start.
//!
//! One measure says how far from physical an inertia is: the triangle excess
//! `δ = I3 − I1 − I2` (kg·m²; a negative moment breaks the triangle inequality too, by at least
//! its size), relative to the largest moment `I3`. Above [`GROSS_DEFECT`] of `I3` the numbers
//! are wrong rather than rounded. That bound survives welding links together: `δ ≤ c·I3` is
//! `δ ≤ c/(2 − c)·tr(I)`, `δ` is subadditive under sums, rotations and the parallel-axis shift
//! (which add positive semi-definite second moments), and the trace is additive; so a body
//! merged from links within the bound is within it.
//!
//! The nearest physical inertia ([`nearest_physical`]) keeps the principal axes and moves the
//! principal moments the shortest Euclidean distance into the physical set (for a set of
//! matrices defined by their eigenvalues, the Frobenius-nearest matrix shares the
//! eigenvectors). The distance is at most `δ` (raising `I1` by `δ` is physical), so no moment
//! changes by more than the defect. A body with mass but no extent about one axis (a rod) gets
//! the smallest moment [`SMALLEST_MOMENT`] allows.

use super::validate::{principal_moments, INERTIA_REL_TOL};
use super::Inertia;
use nalgebra::{Matrix2, Matrix3, SymmetricEigen, Vector2, Vector3};
use std::fmt;

/// Beyond this fraction of the largest principal moment, the triangle excess `I3 − I1 − I2`
/// marks a wrong inertia, not a rounded one (a flat plate is exactly at 0; the vendor files
/// dyngen has met that break it do so by 9% and 20%).
pub const GROSS_DEFECT: f64 = 0.5;

/// The smallest principal moment a repair gives a body with mass, as a fraction of its
/// largest: ten times the rounding `INERTIA_REL_TOL` (1e-6) forgives, so the repaired body is
/// positive definite beyond doubt (a rod of length `L` that thin has a radius of `L/800`).
pub const SMALLEST_MOMENT: f64 = 10.0 * INERTIA_REL_TOL;

/// What is wrong with an inertia.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InertiaDefectKind {
    /// A principal moment below zero (no mass distribution has one).
    NegativeMoment,
    /// `I1 + I2 < I3`: the mass would lie further from every axis than any body allows.
    TriangleInequality,
    /// Positive mass, physical, but a zero principal moment: a body of no thickness about one
    /// axis (a rod), whose inertia is singular.
    NoExtent,
}

/// An inertia that is not one of a real body, with what it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InertiaDefect {
    pub kind: InertiaDefectKind,
    /// Principal moments about the centre of mass, ascending (kg·m²).
    pub moments: [f64; 3],
    /// The body's mass (kg).
    pub mass: f64,
}

impl InertiaDefect {
    /// The triangle excess `I3 − I1 − I2` (kg·m²), the distance to physical that
    /// [`GROSS_DEFECT`] bounds; 0 or less for [`InertiaDefectKind::NoExtent`].
    pub fn excess(&self) -> f64 {
        let [i1, i2, i3] = self.moments;
        i3 - i1 - i2
    }

    /// [`InertiaDefect::excess`] as a fraction of the largest principal moment (infinite when
    /// no moment is positive).
    pub fn relative_excess(&self) -> f64 {
        let largest = self.moments[2];
        if largest > 0.0 {
            self.excess() / largest
        } else if self.excess() > 0.0 {
            f64::INFINITY
        } else {
            0.0
        }
    }

    /// Whether the defect is beyond [`GROSS_DEFECT`]: wrong numbers, not rounded ones.
    pub fn is_gross(&self) -> bool {
        self.exceeds(GROSS_DEFECT)
    }

    /// Whether the triangle excess is beyond `fraction` of the largest moment (with the
    /// rounding `INERTIA_REL_TOL` (1e-6) forgives).
    pub(crate) fn exceeds(&self, fraction: f64) -> bool {
        let [i1, _, i3] = self.moments;
        self.excess() > fraction * i3.max(0.0) + INERTIA_REL_TOL * i1.abs().max(i3.abs())
    }

    /// How far a repair may move a principal moment: the triangle excess, and for a body
    /// without extent the moment it is given.
    pub fn size(&self) -> f64 {
        let largest = self.moments[2].max(0.0);
        match self.kind {
            InertiaDefectKind::NoExtent => SMALLEST_MOMENT * largest - self.moments[0],
            // The projection moves no moment further than the excess, so the largest after it
            // is at most `largest + excess`, and the smallest is raised to that much at most.
            _ => self.excess() + SMALLEST_MOMENT * (largest + self.excess()),
        }
    }
}

impl fmt::Display for InertiaDefect {
    /// The defect in units a person can judge, e.g. `inertia is not physical: triangle
    /// inequality broken by 20%: I1 + I2 = 5.78591e-6 < I3 = 7.2659e-6 kg·m²`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [i1, i2, i3] = self.moments;
        match self.kind {
            InertiaDefectKind::NegativeMoment => write!(
                f,
                "inertia is not physical: principal moment {} kg·m² is negative (principal moments {} kg·m²)",
                short(i1),
                moments_text(&self.moments)
            ),
            InertiaDefectKind::TriangleInequality => write!(
                f,
                "inertia is not physical: triangle inequality broken by {}: I1 + I2 = {} < I3 = {} kg·m²",
                percent(self.relative_excess()),
                short(i1 + i2),
                short(i3)
            ),
            InertiaDefectKind::NoExtent => write!(
                f,
                "inertia is singular: mass {} kg with a principal moment of {} kg·m² (the others {} \
                 and {} kg·m²): no extent about one axis, like a rod of no thickness",
                short(self.mass),
                short(i1),
                short(i2),
                short(i3)
            ),
        }
    }
}

/// What is wrong with the rotational inertia `inertia` (about the centre of mass, finite and
/// symmetric) of a body of `mass`, if anything. The tests and their rounding tolerance are the
/// loader's: `INERTIA_REL_TOL` (1e-6) of the largest moment is forgiven.
pub fn inertia_defect(mass: f64, inertia: &Matrix3<f64>) -> Option<InertiaDefect> {
    let moments = principal_moments(inertia);
    let [i1, i2, i3] = moments;
    let tol = INERTIA_REL_TOL * i1.abs().max(i3.abs());
    let kind = if i1 < -tol {
        InertiaDefectKind::NegativeMoment
    } else if i1 + i2 < i3 - tol {
        InertiaDefectKind::TriangleInequality
    } else if mass > 0.0 && inertia.iter().any(|v| *v != 0.0) && i1 <= tol {
        InertiaDefectKind::NoExtent
    } else {
        return None;
    };
    Some(InertiaDefect { kind, moments, mass })
}

/// The physical rotational inertia nearest to `inertia` (see the module docs): the same
/// principal axes, the principal moments projected onto the physical set, and for a body with
/// mass the smallest moment at least [`SMALLEST_MOMENT`] of the largest. A physical inertia
/// comes back unchanged.
pub fn nearest_physical(mass: f64, inertia: &Matrix3<f64>) -> Matrix3<f64> {
    if inertia_defect(mass, inertia).is_none() {
        return *inertia;
    }
    // Scaled to entries of at most 1, as `principal_moments` does, so nothing overflows.
    let scale = inertia.amax();
    let unit = inertia / scale;
    let eig = SymmetricEigen::new((unit + unit.transpose()) * 0.5);
    let before = eig.eigenvalues;
    let mut after = project_onto_physical(&before);
    if after.max() <= 0.0 {
        // Nothing physical is nearer than no rotational inertia at all: exactly zero (a point
        // mass), not the rounding left by subtracting the tensor from itself.
        return Matrix3::zeros();
    }
    if mass > 0.0 {
        let (smallest, largest) = (after.imin(), after.max());
        after[smallest] = after[smallest].max(SMALLEST_MOMENT * largest);
    }
    // Only the change is rotated back, so entries the repair does not need stay as written.
    let change = eig.eigenvectors * Matrix3::from_diagonal(&(after - before)) * eig.eigenvectors.transpose();
    let repaired = inertia + change * scale;
    (repaired + repaired.transpose()) * 0.5
}

/// The Euclidean projection of principal moments onto the physical set
/// `{x : x_i + x_j ≥ x_k for every k}`. In second moments `s = ½(Σx − 2x)` that set is
/// `s ≥ 0` and `x = B s` with `B = 1 1ᵀ − 1`, so the projection is a non-negative least
/// squares problem in three unknowns: the best of its faces (each a small unconstrained
/// least squares) whose solution is non-negative.
fn project_onto_physical(x: &Vector3<f64>) -> Vector3<f64> {
    let second_moments = Vector3::new(x.y + x.z - x.x, x.x + x.z - x.y, x.x + x.y - x.z) / 2.0;
    if second_moments.min() >= 0.0 {
        return *x;
    }
    let column = |k: usize| Vector3::from_fn(|r, _| if r == k { 0.0 } else { 1.0 });
    let mut best = Vector3::zeros();
    let mut best_distance = x.norm_squared();
    let faces: [&[usize]; 6] = [&[0], &[1], &[2], &[0, 1], &[1, 2], &[0, 2]];
    for face in faces {
        let candidate = match *face {
            [k] => {
                let b = column(k);
                let s = b.dot(x) / 2.0;
                (s >= 0.0).then(|| b * s)
            }
            [i, j] => {
                let (bi, bj) = (column(i), column(j));
                let gram = Matrix2::new(2.0, 1.0, 1.0, 2.0);
                let s = gram.try_inverse().map(|g| g * Vector2::new(bi.dot(x), bj.dot(x)));
                s.filter(|s| s.x >= 0.0 && s.y >= 0.0)
                    .map(|s| bi * s.x + bj * s.y)
            }
            _ => None,
        };
        if let Some(c) = candidate {
            let distance = (c - x).norm_squared();
            if distance < best_distance {
                best = c;
                best_distance = distance;
            }
        }
    }
    best
}

impl Inertia {
    /// What is wrong with this body's inertia, if anything ([`inertia_defect`]).
    pub fn defect(&self) -> Option<InertiaDefect> {
        inertia_defect(self.mass, &self.inertia_com)
    }

    /// The same body with the nearest physical inertia ([`nearest_physical`]).
    pub fn repaired(&self) -> Inertia {
        Inertia {
            inertia_com: nearest_physical(self.mass, &self.inertia_com),
            ..*self
        }
    }
}

/// A number for a message: six significant digits, with an exponent when below 1e-3 or
/// above 1e6 (moments of small links are 1e-6 kg·m² and less).
pub(crate) fn short(v: f64) -> String {
    let r: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    if r != 0.0 && r.is_finite() && !(1e-3..1e6).contains(&r.abs()) {
        format!("{r:e}")
    } else {
        format!("{r}")
    }
}

/// Principal moments as the messages about inertias write them, six significant digits:
/// `[2.30064e-6, 3.48527e-6, 7.2659e-6]`.
pub fn moments_text(m: &[f64; 3]) -> String {
    format!("[{}, {}, {}]", short(m[0]), short(m[1]), short(m[2]))
}

/// A fraction as a percentage a person reads at a glance: `20%`, `0.3%`, `0.004%`.
pub(crate) fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if !p.is_finite() {
        "more than 100%".into()
    } else if p <= 0.0 {
        "0%".into()
    } else if p >= 1.0 {
        format!("{p:.0}%")
    } else {
        // Two significant digits.
        let digits = (1 - p.abs().log10().floor() as i32).max(0) as usize;
        format!("{p:.digits$}%")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a seed (xorshift: the tests need no quality, only repeats).
    fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn diag(m: [f64; 3]) -> Matrix3<f64> {
        Matrix3::from_diagonal(&m.into())
    }

    /// A physical set membership test on moments (any order), with rounding.
    fn physical(m: &[f64; 3]) -> bool {
        let tol = 1e-12 * m.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        (0..3).all(|k| m[(k + 1) % 3] + m[(k + 2) % 3] >= m[k] - tol)
    }

    #[test]
    fn physical_inertias_have_no_defect_and_are_left_alone() {
        for m in [
            [1.0, 1.0, 1.0],
            [1.0, 1.0, 2.0],
            [0.0, 0.0, 0.0],
            [0.1, 0.2, 0.25],
        ] {
            assert_eq!(inertia_defect(1.0, &diag(m)), None, "{m:?}");
            assert_eq!(nearest_physical(1.0, &diag(m)), diag(m));
        }
    }

    #[test]
    fn each_kind_is_recognised() {
        let d = inertia_defect(1e-6, &diag([-3.5e-8, 3.5e-8, 9.1e-8])).unwrap();
        assert_eq!(d.kind, InertiaDefectKind::NegativeMoment);
        assert_eq!(
            d.to_string(),
            "inertia is not physical: principal moment -3.5e-8 kg·m² is negative (principal moments \
             [-3.5e-8, 3.5e-8, 9.1e-8] kg·m²)"
        );
        let d = inertia_defect(0.0096, &diag([2.30064e-6, 3.48527e-6, 7.2659e-6])).unwrap();
        assert_eq!(d.kind, InertiaDefectKind::TriangleInequality);
        assert_eq!(
            d.to_string(),
            "inertia is not physical: triangle inequality broken by 20%: I1 + I2 = 5.78591e-6 < \
             I3 = 7.2659e-6 kg·m²"
        );
        assert!(!d.is_gross());
        let d = inertia_defect(0.0307, &diag([0.0, 0.00012, 0.00012])).unwrap();
        assert_eq!(d.kind, InertiaDefectKind::NoExtent);
        assert_eq!(
            d.to_string(),
            "inertia is singular: mass 0.0307 kg with a principal moment of 0 kg·m² (the others \
             1.2e-4 and 1.2e-4 kg·m²): no extent about one axis, like a rod of no thickness"
        );
        // Without mass, a rod is only a frame with an inertia (the loader warns otherwise).
        assert_eq!(inertia_defect(0.0, &diag([0.0, 0.00012, 0.00012])), None);
    }

    #[test]
    fn gross_is_beyond_half_the_largest_moment() {
        assert!(!inertia_defect(1.0, &diag([0.1, 0.1, 0.39])).unwrap().is_gross());
        assert!(inertia_defect(1.0, &diag([0.1, 0.1, 0.41])).unwrap().is_gross());
        assert!(inertia_defect(1.0, &diag([-1.0, -1.0, -1.0])).unwrap().is_gross());
        assert!(inertia_defect(1.0, &diag([-1.0, 0.0, 0.0])).unwrap().is_gross());
    }

    #[test]
    fn repairs_are_physical_and_move_no_moment_further_than_the_defect() {
        let mut next = uniform(0x1234_5678_9abc_def0_u64);
        for _ in 0..2000 {
            let moments = [next() * 2.0 - 0.5, next(), next() * 3.0];
            let (a, b, c) = (next() * 6.0, next() * 6.0, next() * 6.0);
            let r = nalgebra::Rotation3::from_euler_angles(a, b, c).into_inner();
            let tensor = r * diag(moments) * r.transpose();
            let mass = if next() < 0.2 { 0.0 } else { next() };
            let Some(defect) = inertia_defect(mass, &tensor) else {
                continue;
            };
            let repaired = nearest_physical(mass, &tensor);
            assert_eq!(inertia_defect(mass, &repaired), None, "{moments:?} → {repaired}");
            let after = principal_moments(&repaired);
            assert!(physical(&after), "{after:?}");
            let before = defect.moments;
            for k in 0..3 {
                assert!(
                    (after[k] - before[k]).abs() <= defect.size() * (1.0 + 1e-9) + 1e-12,
                    "{before:?} → {after:?}, defect {}",
                    defect.size()
                );
            }
            // The principal axes stay: the change commutes with the original tensor.
            let change = repaired - tensor;
            assert!((change * tensor - tensor * change).amax() < 1e-9, "{moments:?}");
        }
    }

    /// The projection is the nearest physical point: no physical moment triple (`B s`, `s ≥ 0`,
    /// drawn around it) is nearer.
    #[test]
    fn the_projection_is_nearer_than_any_physical_point() {
        let mut next = uniform(0x5eed_0f7e_57ab_cdef_u64);
        for _ in 0..300 {
            let x = Vector3::new(next() * 2.0 - 1.0, next() * 2.0 - 0.5, next() * 3.0);
            let p = project_onto_physical(&x);
            let s = Vector3::new(p.y + p.z - p.x, p.x + p.z - p.y, p.x + p.y - p.z) / 2.0;
            assert!(s.min() >= -1e-12, "{p} is not physical");
            let nearest = (p - x).norm();
            for _ in 0..200 {
                let t = (s + Vector3::new(next(), next(), next()) * 0.3 - Vector3::repeat(0.1))
                    .map(|v| v.max(0.0));
                let y = Vector3::new(t.y + t.z, t.x + t.z, t.x + t.y);
                assert!((y - x).norm() >= nearest - 1e-12, "{x} → {p}, but {y} is nearer");
            }
        }
    }

    /// The bound is closed under welding (module docs): links up to exactly half their largest
    /// moment, turned, moved and merged in twos and threes, give bodies within it.
    #[test]
    fn bodies_welded_from_links_within_the_bound_stay_within_it() {
        let mut next = uniform(0x0ddb_a11c_afe5_eed5_u64);
        let mut largest_seen: f64 = 0.0;
        for _ in 0..3000 {
            let parts = 2 + (next() * 2.0) as usize;
            let mut body: Option<Inertia> = None;
            for _ in 0..parts {
                // Moments with a triangle excess of `e` (at most the bound) and `I3 = 1`, scaled.
                let e = if next() < 0.3 {
                    GROSS_DEFECT
                } else {
                    next() * GROSS_DEFECT
                };
                let i1 = -e + next() * (1.0 - e) / 2.0 + next() * e;
                let scale = 10f64.powf(next() * 4.0 - 4.0);
                let moments = [i1, 1.0 - e - i1, 1.0].map(|m| m * scale);
                let link = Inertia {
                    mass: if next() < 0.2 { 0.0 } else { next() * 3.0 },
                    com: Vector3::new(next(), next(), next()) * 0.2,
                    inertia_com: diag(moments),
                };
                let pose = super::super::from_xyz_rpy(
                    [next() - 0.5, next() - 0.5, next() - 0.5],
                    [next() * 6.0, next() * 6.0, next() * 6.0],
                );
                let part = link.transformed(&pose);
                body = Some(body.map_or(part, |b| b.merged(&part)));
            }
            let body = body.expect("parts");
            if let Some(defect) = body.defect() {
                largest_seen = largest_seen.max(defect.relative_excess());
                assert!(!defect.is_gross(), "{:?} from {parts} parts", defect.moments);
            }
        }
        assert!(largest_seen > 0.3, "the bound was approached: {largest_seen}");
    }

    #[test]
    fn a_triangle_defect_moves_each_moment_by_a_third() {
        let after = principal_moments(&nearest_physical(1.0, &diag([1.0, 1.0, 2.6])));
        for (a, e) in after.iter().zip([1.2, 1.2, 2.4]) {
            assert!((a - e).abs() < 1e-12, "{after:?}");
        }
    }

    #[test]
    fn a_rod_gets_the_smallest_moment() {
        let after = principal_moments(&nearest_physical(0.0307, &diag([0.0, 0.00012, 0.00012])));
        for (a, e) in after.iter().zip([SMALLEST_MOMENT * 0.00012, 0.00012, 0.00012]) {
            assert!((a - e).abs() < 1e-18, "{after:?}");
        }
    }

    #[test]
    fn percentages_read_at_a_glance() {
        assert_eq!(percent(0.204), "20%");
        assert_eq!(percent(0.0031), "0.31%");
        assert_eq!(percent(0.00004), "0.0040%");
        assert_eq!(percent(f64::INFINITY), "more than 100%");
    }
}
