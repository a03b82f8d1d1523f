//! The adaptation gain `Γ` (diagonal) and the update `θ̂̇ = −Γ Yᵀ r` (Lemma 3).

use nalgebra::{SMatrix, SVector};

/// Per-kind adaptation gains: mass, first moment `m·c`, second moment `I`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GammaByKind {
    pub mass: f64,
    pub first_moment: f64,
    pub inertia: f64,
}

impl Default for GammaByKind {
    /// `[100, 10, 1]` over `[m, m·c, I]`: what worked in the reference prototype at 1 kHz.
    fn default() -> Self {
        GammaByKind {
            mass: 100.0,
            first_moment: 10.0,
            inertia: 1.0,
        }
    }
}

impl GammaByKind {
    /// The diagonal of `Γ` for parameters named as the generator names them. The kind is read
    /// from the name's first term: `m[…]` → mass, `mc…[…]` → first moment, `I…[…]` → inertia.
    /// A base parameter (a combination such as `"Izz[link1] + Iyy[link2] + …"`) takes the kind
    /// of its first term; a name that matches no kind gets the smallest (inertia) gain, which
    /// is the conservative choice in discrete time. For anything else pass your own diagonal.
    pub fn diagonal<const M: usize>(&self, names: &[&str; M]) -> SVector<f64, M> {
        SVector::from_fn(|i, _| {
            let first = names[i].trim_start_matches(['-', '+', ' ', '(']);
            if first.starts_with("m[") {
                self.mass
            } else if first.starts_with("mc") {
                self.first_moment
            } else {
                self.inertia
            }
        })
    }
}

/// `θ̂̇ = −Γ Yᵀ r` with diagonal `Γ`.
#[inline]
pub fn parameter_rate<const N: usize, const M: usize>(
    gamma: &SVector<f64, M>,
    y: &SMatrix<f64, N, M>,
    r: &SVector<f64, N>,
) -> SVector<f64, M> {
    let ytr = y.tr_mul(r);
    SVector::from_fn(|i, _| -gamma[i] * ytr[i])
}
