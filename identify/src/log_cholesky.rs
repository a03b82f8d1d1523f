//! The free numbers of a consistent body: every value of them is a physically valid rigid
//! body, with a margin the description loader can never refuse.
//!
//! A body's ten inertial parameters are consistent when its pseudo-inertia
//! `J = [[Σ, h], [hᵀ, m]]` (`Σ = ½ tr(I)·1 − I`, `h = m c`, `I` about the body origin) is
//! positive definite (Wensing, Kim & Slotine 2017); equivalently `m > 0` and the
//! pseudo-inertia about the centre of mass, `Σ_c = Σ − m c cᵀ`, is positive definite. Its
//! principal values `σ_i` make the principal moments `I_i = tr(Σ_c) − σ_i`, so `Σ_c ≻ 0` is
//! the triangle inequality, strictly.
//!
//! Strictly is not enough for a file: the loader refuses an inertia whose smallest principal
//! moment is below 10⁻⁶ of the largest, and a number rounded in the file could cross that
//! line. So the map keeps every body inside the cone `Σ_c ⪰ δ tr(Σ_c)·1` ([`MARGIN`]), where
//! `I_min ≥ 2δ I_max` and the triangle inequality holds with `2δ tr(Σ_c)` to spare:
//!
//! ```text
//! m = e^{2α},  c = L t,  D = L [[e^{d₁}, 0, 0], [l₂₁, e^{d₂}, 0], [l₃₁, l₃₂, e^{d₃}]],
//! S = D Dᵀ,  Σ_c = m (S + κ tr(S)·1),  κ = δ / (1 − 3δ)
//! ```
//!
//! (log-Cholesky, Rucker & Wensing 2022, with the margin added and the COM split out). `L` is a
//! length of the body (its reach in the description), so that `t` and `l` are of order one for
//! a wrist as for a two-metre arm: free numbers of one size make the optimiser's steps and the
//! prior's weights mean the same on every body.

use nalgebra::{Matrix3, Matrix4, SMatrix, Vector3};

/// Relative margin `δ` of every consistent body: `Σ_c ⪰ δ tr(Σ_c)·1`, so that the smallest
/// principal moment is at least `2δ` of the largest, twenty times the loader's tolerance
/// (`INERTIA_REL_TOL`, 10⁻⁶), and a thin rod of radius 1 cm and length 1 m (ratio 6·10⁻⁴) is
/// still inside.
pub(crate) const MARGIN: f64 = 1e-5;
const KAPPA: f64 = MARGIN / (1.0 - 3.0 * MARGIN);
/// A body brought inside the cone keeps its smallest principal parts at least this fraction
/// of its largest.
const INSIDE_FLOOR: f64 = 1e-6;

/// The pseudo-inertia of one body's ten parameters `[m, mc, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
pub(crate) fn pseudo_inertia(p: &[f64]) -> Matrix4<f64> {
    let inertia = Matrix3::new(p[4], p[5], p[7], p[5], p[6], p[8], p[7], p[8], p[9]);
    let sigma = Matrix3::identity() * (0.5 * inertia.trace()) - inertia;
    let mut j = Matrix4::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&sigma);
    j.fixed_view_mut::<3, 1>(0, 3)
        .copy_from(&Vector3::new(p[1], p[2], p[3]));
    j.fixed_view_mut::<1, 3>(3, 0)
        .copy_from(&Vector3::new(p[1], p[2], p[3]).transpose());
    j[(3, 3)] = p[0];
    j
}

/// The ten parameters of a pseudo-inertia (linear, so it maps derivatives too).
pub(crate) fn parameters_of(j: &Matrix4<f64>) -> [f64; 10] {
    let sigma = j.fixed_view::<3, 3>(0, 0).into_owned();
    let inertia = Matrix3::identity() * sigma.trace() - sigma;
    [
        j[(3, 3)],
        j[(0, 3)],
        j[(1, 3)],
        j[(2, 3)],
        inertia[(0, 0)],
        inertia[(0, 1)],
        inertia[(1, 1)],
        inertia[(0, 2)],
        inertia[(1, 2)],
        inertia[(2, 2)],
    ]
}

/// The pseudo-inertia of mass `m`, centre of mass `c` and COM pseudo-inertia `sigma_c`.
fn assemble(m: f64, c: &Vector3<f64>, sigma_c: &Matrix3<f64>) -> Matrix4<f64> {
    let mut j = Matrix4::zeros();
    j.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(sigma_c + c * c.transpose() * m));
    j.fixed_view_mut::<3, 1>(0, 3).copy_from(&(c * m));
    j.fixed_view_mut::<1, 3>(3, 0).copy_from(&(c * m).transpose());
    j[(3, 3)] = m;
    j
}

/// Positions of the three off-diagonal entries of `D` among the free numbers, and their
/// (row, column).
const OFF_DIAGONAL: [(usize, usize, usize); 3] = [(4, 1, 0), (5, 2, 0), (6, 2, 1)];

/// One body's free numbers `(α, d₁, d₂, d₃, l₂₁, l₃₁, l₃₂, t₁, t₂, t₃)` ↔ its ten parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyMap {
    /// The body's length `L` (m).
    pub length: f64,
}

impl BodyMap {
    fn factor(&self, phi: &[f64]) -> (f64, Matrix3<f64>, Vector3<f64>) {
        let l = self.length;
        let mut d = Matrix3::zeros();
        for p in 0..3 {
            d[(p, p)] = l * phi[1 + p].exp();
        }
        for (k, r, c) in OFF_DIAGONAL {
            d[(r, c)] = l * phi[k];
        }
        let c = Vector3::new(phi[7], phi[8], phi[9]) * l;
        ((2.0 * phi[0]).exp(), d, c)
    }

    fn sigma_c(m: f64, s: &Matrix3<f64>) -> Matrix3<f64> {
        (s + Matrix3::identity() * (KAPPA * s.trace())) * m
    }

    /// The ten parameters of free numbers `phi`.
    pub fn parameters(&self, phi: &[f64]) -> [f64; 10] {
        let (m, d, c) = self.factor(phi);
        parameters_of(&assemble(m, &c, &Self::sigma_c(m, &(d * d.transpose()))))
    }

    /// `∂θ/∂φ` at `phi`: column `k` is the derivative by free number `k`.
    pub fn jacobian(&self, phi: &[f64]) -> SMatrix<f64, 10, 10> {
        let (m, d, c) = self.factor(phi);
        let mut jac = SMatrix::<f64, 10, 10>::zeros();
        let column = |dj: Matrix4<f64>| SMatrix::<f64, 10, 1>::from(parameters_of(&dj));
        // Every parameter is proportional to m = e^{2α}.
        jac.set_column(
            0,
            &(column(assemble(m, &c, &Self::sigma_c(m, &(d * d.transpose())))) * 2.0),
        );
        let through_d = |dd: Matrix3<f64>| {
            let ds = dd * d.transpose() + d * dd.transpose();
            let mut dj = Matrix4::zeros();
            dj.fixed_view_mut::<3, 3>(0, 0).copy_from(&Self::sigma_c(m, &ds));
            column(dj)
        };
        for p in 0..3 {
            let mut dd = Matrix3::zeros();
            dd[(p, p)] = d[(p, p)];
            jac.set_column(1 + p, &through_d(dd));
        }
        for (k, r, col) in OFF_DIAGONAL {
            let mut dd = Matrix3::zeros();
            dd[(r, col)] = self.length;
            jac.set_column(k, &through_d(dd));
        }
        for i in 0..3 {
            let dc = Vector3::ith(i, self.length);
            let mut dj = Matrix4::zeros();
            dj.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&((dc * c.transpose() + c * dc.transpose()) * m));
            dj.fixed_view_mut::<3, 1>(0, 3).copy_from(&(dc * m));
            dj.fixed_view_mut::<1, 3>(3, 0).copy_from(&(dc * m).transpose());
            jac.set_column(7 + i, &column(dj));
        }
        jac
    }

    /// Free numbers of the consistent body nearest `p` (the same body when it is well inside
    /// the cone): the pseudo-inertia's eigenvalues, in the body's length units, raised to
    /// [`INSIDE_FLOOR`] of the largest, then the COM part likewise, inside the margin. `None`
    /// for a body with nothing positive to keep (no mass, no inertia).
    pub fn free_numbers(&self, p: &[f64]) -> Option<[f64; 10]> {
        let l = self.length;
        let t = Matrix4::from_diagonal(&nalgebra::Vector4::new(1.0 / l, 1.0 / l, 1.0 / l, 1.0));
        let scaled = t * pseudo_inertia(p) * t;
        let eigen = scaled.symmetric_eigen();
        let largest = eigen.eigenvalues.max();
        if !(largest > 0.0 && largest.is_finite()) {
            return None;
        }
        let clipped = eigen.eigenvalues.map(|v| v.max(INSIDE_FLOOR * largest));
        let scaled = eigen.eigenvectors * Matrix4::from_diagonal(&clipped) * eigen.eigenvectors.transpose();
        let t_inv = Matrix4::from_diagonal(&nalgebra::Vector4::new(l, l, l, 1.0));
        let j = t_inv * scaled * t_inv;
        let m = j[(3, 3)];
        let h = Vector3::new(j[(0, 3)], j[(1, 3)], j[(2, 3)]);
        let c = h / m;
        let sigma = j.fixed_view::<3, 3>(0, 0).into_owned();
        let per_mass = (sigma - c * c.transpose() * m) / m;
        let per_mass = (per_mass + per_mass.transpose()) * 0.5;
        // Σ_c/m = S + κ tr(S)·1 ⇔ S = Σ_c/m − κ/(1+3κ) tr(Σ_c/m)·1.
        let trace = per_mass.trace().max(f64::MIN_POSITIVE);
        let s = per_mass - Matrix3::identity() * (KAPPA / (1.0 + 3.0 * KAPPA) * trace);
        let eigen = s.symmetric_eigen();
        let s = eigen.eigenvectors
            * Matrix3::from_diagonal(&eigen.eigenvalues.map(|v| v.max(INSIDE_FLOOR * trace)))
            * eigen.eigenvectors.transpose();
        let d = ((s + s.transpose()) * 0.5).cholesky()?.l();
        let mut phi = [0.0; 10];
        phi[0] = 0.5 * m.ln();
        for k in 0..3 {
            phi[1 + k] = (d[(k, k)] / l).ln();
        }
        for (k, r, col) in OFF_DIAGONAL {
            phi[k] = d[(r, col)] / l;
        }
        for k in 0..3 {
            phi[7 + k] = c[k] / l;
        }
        phi.iter().all(|v| v.is_finite()).then_some(phi)
    }
}

/// Smallest principal value of a body's COM pseudo-inertia relative to its trace: at least
/// [`MARGIN`] for a body the consistent estimate makes, 0 on the boundary of physical
/// validity, negative (or NaN without mass) beyond it.
pub(crate) fn relative_margin(p: &[f64]) -> f64 {
    let j = pseudo_inertia(p);
    let m = j[(3, 3)];
    if m.is_nan() || m <= 0.0 {
        return if m == 0.0 { 0.0 } else { -1.0 };
    }
    let h = Vector3::new(j[(0, 3)], j[(1, 3)], j[(2, 3)]);
    let sigma_c = j.fixed_view::<3, 3>(0, 0).into_owned() - h * h.transpose() / m;
    let e = ((sigma_c + sigma_c.transpose()) * 0.5).symmetric_eigenvalues();
    let trace = e.sum();
    if trace > 0.0 {
        e.min() / trace
    } else {
        e.min()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn phi() -> [f64; 10] {
        [0.7, -0.3, 0.2, -1.1, 0.4, -0.25, 0.1, 0.3, -0.6, 1.2]
    }

    /// The analytic Jacobian against central differences.
    #[test]
    fn jacobian_matches_differences() {
        let map = BodyMap { length: 0.4 };
        let phi = phi();
        let jac = map.jacobian(&phi);
        for k in 0..10 {
            let h = 1e-6;
            let (mut up, mut down) = (phi, phi);
            up[k] += h;
            down[k] -= h;
            let (pu, pd) = (map.parameters(&up), map.parameters(&down));
            for row in 0..10 {
                let fd = (pu[row] - pd[row]) / (2.0 * h);
                assert!(
                    (fd - jac[(row, k)]).abs() <= 1e-7 * (1.0 + fd.abs()),
                    "∂θ{row}/∂φ{k}: {} vs {fd}",
                    jac[(row, k)]
                );
            }
        }
    }

    /// A body inside the cone comes back from its parameters unchanged, and every value of the
    /// free numbers keeps the margin.
    #[test]
    fn free_numbers_invert_parameters_and_keep_the_margin() {
        let map = BodyMap { length: 0.4 };
        let phi = phi();
        let p = map.parameters(&phi);
        let back = map.free_numbers(&p).expect("a body");
        for k in 0..10 {
            assert!((back[k] - phi[k]).abs() <= 1e-9, "{k}: {} vs {}", back[k], phi[k]);
        }
        let mut thin = phi;
        thin[3] = -40.0;
        assert!(relative_margin(&map.parameters(&thin)) >= 0.999 * MARGIN);
    }
}
