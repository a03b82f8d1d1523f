//! Rigid-body inertia in the ten standard parameters, which all dynamics is linear in.

use super::{Force, Motion, Transform, Vec3};
use crate::scalar::Scalar;
use dyngen_runtime::PARAMETERS_PER_BODY;

/// Spatial inertia about a frame origin: mass `m`, first moment `h = m·c`, and the rotational
/// inertia about the origin as the symmetric entries `[Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidInertia<S> {
    pub m: S,
    pub h: Vec3<S>,
    pub i: [S; 6],
}

impl<S: Scalar> RigidInertia<S> {
    /// From the standard parameters `[m, mcx, mcy, mcz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
    pub fn from_parameters(p: &[S; PARAMETERS_PER_BODY]) -> Self {
        RigidInertia {
            m: p[0],
            h: Vec3([p[1], p[2], p[3]]),
            i: [p[4], p[5], p[6], p[7], p[8], p[9]],
        }
    }

    /// The inertia of parameter `k` set to one and the others to zero. Dynamics is linear in
    /// the parameters, so a body's force with this "inertia" is column `k` of its regressor.
    pub fn unit(k: usize) -> Self {
        let mut p = [S::zero(); PARAMETERS_PER_BODY];
        p[k] = S::one();
        Self::from_parameters(&p)
    }

    pub fn zero() -> Self {
        Self::from_parameters(&[S::zero(); PARAMETERS_PER_BODY])
    }

    /// Rotational inertia about the origin times `w`.
    fn rot_mul(&self, w: &Vec3<S>) -> Vec3<S> {
        let [xx, xy, yy, xz, yz, zz] = self.i;
        let [a, b, c] = w.0;
        Vec3([
            xx * a + xy * b + xz * c,
            xy * a + yy * b + yz * c,
            xz * a + yz * b + zz * c,
        ])
    }

    /// Momentum `I·m` of a motion.
    pub fn mul_motion(&self, m: &Motion<S>) -> Force<S> {
        Force {
            ang: self.rot_mul(&m.ang) + self.h.cross(&m.lin),
            lin: m.lin.scale(self.m) - self.h.cross(&m.ang),
        }
    }

    /// The body force `I ẇ + B(I, v)·w`, with the body operator
    /// `B(I, v)·w = ½ [v ×* (I w) + w ×* (I v) − I (v × w)]` (Echeandia & Wensing 2021):
    /// `B(I, v)·v = v ×* I v`, and `B + Bᵀ = İ`, which makes the Coriolis matrix
    /// Christoffel-consistent.
    ///
    /// Expanded by the triple-product identities, with `v = (ω, u)`, `w = (ω_w, ·)`,
    /// `ẇ = (α, β)` and `ω̂ = ω_w / 2`:
    /// - `n = J (α − ω × ω̂) + ω × J ω̂ + ω̂ × J ω + h × β + ω_w (h·u) − u (h·ω_w)`,
    /// - `f = m (β + ω_w × u) − h × α − h (ω·ω_w) + ω (h·ω_w)`.
    ///
    /// The definition's terms cancel pairwise (`u × u_w + u_w × u`, and four dot products
    /// along `h`), and `w`'s linear part drops out; a simplifier that folds constants does not
    /// see such cancellations, so written as the definition, each of a regressor's ten unit
    /// inertias paid for them.
    pub fn body_force(&self, v: &Motion<S>, w: &Motion<S>, wdot: &Motion<S>) -> Force<S> {
        let (omega, u, omega_w) = (&v.ang, &v.lin, &w.ang);
        let (alpha, beta) = (&wdot.ang, &wdot.lin);
        let h = &self.h;
        let half_w = omega_w.scale(S::from_f64(0.5));
        let h_omega_w = h.dot(omega_w);
        let rotational = self.rot_mul(&(*alpha - omega.cross(&half_w)))
            + omega.cross(&self.rot_mul(&half_w))
            + half_w.cross(&self.rot_mul(omega));
        Force {
            ang: rotational + h.cross(beta) + omega_w.scale(h.dot(u)) - u.scale(h_omega_w),
            lin: (*beta + omega_w.cross(u)).scale(self.m) - h.cross(alpha) - h.scale(omega.dot(omega_w))
                + omega.scale(h_omega_w),
        }
    }

    /// The Newton–Euler force `I a + v ×* (I v)` (the body force at `w = v`), expanded as
    /// [`Self::body_force`] is: `n = J α + ω × J ω + h × β + ω (h·u) − u (h·ω)`,
    /// `f = m (β + ω × u) − h × α − h (ω·ω) + ω (h·ω)`, with `v = (ω, u)`, `a = (α, β)`.
    pub fn newton_euler_force(&self, v: &Motion<S>, a: &Motion<S>) -> Force<S> {
        let (omega, u) = (&v.ang, &v.lin);
        let (alpha, beta) = (&a.ang, &a.lin);
        let h = &self.h;
        let h_omega = h.dot(omega);
        Force {
            ang: self.rot_mul(alpha)
                + omega.cross(&self.rot_mul(omega))
                + h.cross(beta)
                + omega.scale(h.dot(u))
                - u.scale(h_omega),
            lin: (*beta + omega.cross(u)).scale(self.m) - h.cross(alpha) - h.scale(omega.dot(omega))
                + omega.scale(h_omega),
        }
    }

    /// The force about the origin of a body turning at `ω` with angular acceleration `α`,
    /// whose origin accelerates at `a` (the classical acceleration, not the spatial one):
    /// `n = J α + ω × J ω + h × a`, `f = m a + α × h + ω × (ω × h)`. It is
    /// [`Self::newton_euler_force`] at `a = β + ω × u`, without the origin's velocity `u`.
    pub fn origin_force(&self, omega: &Vec3<S>, alpha: &Vec3<S>, a: &Vec3<S>) -> Force<S> {
        let h = &self.h;
        Force {
            ang: self.rot_mul(alpha) + omega.cross(&self.rot_mul(omega)) + h.cross(a),
            lin: a.scale(self.m) + alpha.cross(h) + omega.cross(&omega.cross(h)),
        }
    }

    /// The time derivative `İ = v ×* I − I (v ×)` of this inertia moving with velocity `v`
    /// (angular `ω`, origin velocity `u`), itself of rigid-inertia shape:
    /// `ṁ = 0`, `ḣ = ω × h + m u`, `İ_O = [ω×] I_O − I_O [ω×] + 2 (u·h) 1 − h uᵀ − u hᵀ`.
    pub fn derivative(&self, v: &Motion<S>) -> RigidInertia<S> {
        let (w, u, h) = (&v.ang, &v.lin, &self.h);
        let [xx, xy, yy, xz, yz, zz] = self.i;
        let full = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
        // ([ω×] I)_ij = ω_{i+1} I_{i+2, j} − ω_{i+2} I_{i+1, j}; the commutator is its symmetric part doubled.
        let wi = |i: usize, j: usize| {
            w.0[(i + 1) % 3] * full[(i + 2) % 3][j] - w.0[(i + 2) % 3] * full[(i + 1) % 3][j]
        };
        let two_uh = S::from_f64(2.0) * u.dot(h);
        let entry = |i: usize, j: usize| {
            let commutator = wi(i, j) + wi(j, i);
            let shift = h.0[i] * u.0[j] + u.0[i] * h.0[j];
            if i == j {
                commutator + two_uh - shift
            } else {
                commutator - shift
            }
        };
        RigidInertia {
            m: S::zero(),
            h: w.cross(h) + u.scale(self.m),
            i: [
                entry(0, 0),
                entry(0, 1),
                entry(1, 1),
                entry(0, 2),
                entry(1, 2),
                entry(2, 2),
            ],
        }
    }

    /// The same inertia expressed in the parent frame of `x` (this inertia is in the child frame).
    pub fn to_parent(&self, x: &Transform<S>) -> RigidInertia<S> {
        let t = x.pos;
        let hr = x.rot.mul_vec(&self.h);
        // R I Rᵀ, then the shift of the reference point from the child origin to the parent's.
        let [xx, xy, yy, xz, yz, zz] = self.i;
        let full = super::Mat3([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]);
        let r = x.rot * full * x.rot.transpose();
        let two = S::from_f64(2.0);
        let diag = self.m * t.dot(&t) + two * t.dot(&hr);
        let off = |a: usize, b: usize| self.m * t.0[a] * t.0[b] + t.0[a] * hr.0[b] + hr.0[a] * t.0[b];
        RigidInertia {
            m: self.m,
            h: hr + t.scale(self.m),
            i: [
                r.0[0][0] + diag - off(0, 0),
                r.0[0][1] - off(0, 1),
                r.0[1][1] + diag - off(1, 1),
                r.0[0][2] - off(0, 2),
                r.0[1][2] - off(1, 2),
                r.0[2][2] + diag - off(2, 2),
            ],
        }
    }
}

impl<S: Scalar> std::ops::Add for RigidInertia<S> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        RigidInertia {
            m: self.m + o.m,
            h: self.h + o.h,
            i: std::array::from_fn(|k| self.i[k] + o.i[k]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::RigidInertia;
    use crate::spatial::{Force, Motion, Vec3};
    use proptest::prelude::*;

    fn vec3() -> impl Strategy<Value = Vec3<f64>> {
        prop::array::uniform3(-3.0..3.0f64).prop_map(Vec3)
    }

    fn motion() -> impl Strategy<Value = Motion<f64>> {
        (vec3(), vec3()).prop_map(|(ang, lin)| Motion { ang, lin })
    }

    /// `I ẇ + ½ [v ×* (I w) + w ×* (I v) − I (v × w)]` term by term, as defined.
    fn by_definition(
        i: &RigidInertia<f64>,
        v: &Motion<f64>,
        w: &Motion<f64>,
        wdot: &Motion<f64>,
    ) -> Force<f64> {
        let sum = v.cross_force(&i.mul_motion(w)) + w.cross_force(&i.mul_motion(v))
            - i.mul_motion(&v.cross_motion(w));
        i.mul_motion(wdot)
            + Force {
                ang: sum.ang.scale(0.5),
                lin: sum.lin.scale(0.5),
            }
    }

    proptest! {
        /// The expanded Newton–Euler force equals `I a + v ×* (I v)` for any parameters.
        #[test]
        fn newton_euler_force_equals_its_definition(
            p in prop::array::uniform10(-2.0..2.0f64),
            v in motion(),
            a in motion(),
        ) {
            let i = RigidInertia::from_parameters(&p);
            let want = i.mul_motion(&a) + v.cross_force(&i.mul_motion(&v));
            let got = i.newton_euler_force(&v, &a);
            for (g, e) in got.ang.0.iter().chain(&got.lin.0).zip(want.ang.0.iter().chain(&want.lin.0)) {
                prop_assert!((g - e).abs() <= 1e-12 * (1.0 + e.abs()), "{g} vs {e}");
            }
        }

        /// The expanded body force equals the definition for any inertia parameters (the
        /// identity is linear in them, so no physical-consistency condition is needed).
        #[test]
        fn body_force_equals_its_definition(
            p in prop::array::uniform10(-2.0..2.0f64),
            v in motion(),
            w in motion(),
            wdot in motion(),
        ) {
            let i = RigidInertia::from_parameters(&p);
            let (got, want) = (i.body_force(&v, &w, &wdot), by_definition(&i, &v, &w, &wdot));
            for (g, e) in got.ang.0.iter().chain(&got.lin.0).zip(want.ang.0.iter().chain(&want.lin.0)) {
                prop_assert!((g - e).abs() <= 1e-12 * (1.0 + e.abs()), "{g} vs {e}");
            }
        }
    }
}
