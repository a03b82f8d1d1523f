//! The derivatives of constrained forward dynamics with respect to the state, assembled over
//! what a robot with contacts generates (Pinocchio's `computeConstraintDynamicsDerivatives`).
//!
//! At the solution `(a, λ)`, `F = ID(q, ν, a) − Jᵀ λ − τ = 0` and
//! `G = J a + drift + K_p e + K_d J ν = 0`. Along a direction of the state with `a` and `λ`
//! held, their tangents `Ḟ`, `Ġ` give the solution's change from the system forward dynamics
//! solves, `M ȧ − Jᵀ λ̇ = −Ḟ`, `J ȧ = −Ġ`: with `Y = −M⁻¹ Ḟ` (forward dynamics' change under
//! the forces held), `λ̇ = −K⁻¹ (Ġ + J Y)` and `ȧ = Y + M⁻¹ Jᵀ λ̇`, `K = J M⁻¹ Jᵀ`. The robot
//! generates `Y` for every direction of `q` and `ν` at once
//! ([`ContactDynamics::contact_forward_dynamics_derivatives`], `M⁻¹` applied through its tree
//! factor) and `∂(J a + drift)/∂x` ([`ContactDynamics::contact_acceleration_derivatives`]);
//! [`assemble_derivatives`] factors `K` once and solves every column with it. Along `τ`, `Ḟ = −I`, `Ġ = 0`:
//! `∂λ/∂τ = −K⁻¹ (M⁻¹ Jᵀ)ᵀ`, `∂a/∂τ = M⁻¹ + M⁻¹ Jᵀ ∂λ/∂τ`.
//!
//! The Baumgarte terms: `K_d J ν` adds `K_d ∂(J ν)/∂q` (the rows' acceleration taken at
//! `a + K_d ν`, being linear in `a`) and `K_d J` along `ν`; `K_p e` adds `K_p ∂e/∂q`, which for a
//! point is its rows `J` in world-aligned axes and `J + [e]× Ω` in its own (`Ω` the angular rows
//! of its frame's local Jacobian: the axes turn under the error). A frame's error is a `log₆`,
//! whose derivative is not taken: stabilised frame contacts are refused, as the generic
//! dynamics refuse them.

use super::dense;
use super::kind::ContactKind;
use super::robot::{placement_errors, ContactDynamics};
use super::solve::{factor_delassus, ContactError, ContactSolution, Stabilisation};
use super::system::ContactMatrices;
use crate::ReferenceFrame;
use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, OMatrix, SMatrix};

/// `(∂a/∂x, ∂λ/∂x)` of constrained forward dynamics for `x` each of `q` (in its tangent space,
/// `q ⊕ δ`), `ν` and `τ`: `NV × NV` for the acceleration, `NC × NV` for the forces.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstrainedDerivatives<NV: Dim, NC: Dim>
where
    DefaultAllocator: Allocator<NV, NV> + Allocator<NC, NV>,
{
    pub acceleration_q: OMatrix<f64, NV, NV>,
    pub acceleration_v: OMatrix<f64, NV, NV>,
    pub acceleration_tau: OMatrix<f64, NV, NV>,
    pub forces_q: OMatrix<f64, NC, NV>,
    pub forces_v: OMatrix<f64, NC, NV>,
    pub forces_tau: OMatrix<f64, NC, NV>,
}

/// The derivatives of [`constrained_forward_dynamics`](super::constrained_forward_dynamics)
/// at its `solution` (the same `stabilisation`; the solve may have been proximal, the
/// derivatives are those of the exact solve at that solution, as Pinocchio's). Refused where
/// the rows are redundant, and for a stabilised frame contact (module docs).
pub fn constrained_forward_dynamics_derivatives<
    R: ContactDynamics<NV, NC>,
    const NV: usize,
    const NC: usize,
>(
    t: &R::Trig,
    v: &SMatrix<f64, NV, 1>,
    solution: &ContactSolution<Const<NV>, Const<NC>>,
    stabilisation: Option<Stabilisation<'_>>,
) -> Result<ConstrainedDerivatives<Const<NV>, Const<NC>>, ContactError> {
    let (a, lambda) = (&solution.acceleration, &solution.forces);
    let ContactMatrices {
        jacobian,
        response,
        delassus,
    } = R::contact_matrices(t);
    let acceleration = match stabilisation {
        None => R::contact_acceleration_derivatives(t, v, a),
        Some(s) => {
            let kinds = R::CONTACT_KINDS.iter();
            if kinds.into_iter().any(|&k| k == ContactKind::Frame) {
                return Err(ContactError::Settings(
                    "the derivatives of a stabilised frame contact (its error is a log₆) are not computed",
                ));
            }
            let (g_q, g_v) = R::contact_acceleration_derivatives(t, v, &(a + v * s.kd));
            let error = error_derivatives::<R, NV, NC>(t, &jacobian, &s)?;
            (g_q + error * s.kp, g_v + jacobian * s.kd)
        }
    };
    assemble(
        &jacobian,
        &response,
        delassus,
        R::torque_response(t),
        R::contact_forward_dynamics_derivatives(t, v, a, lambda),
        acceleration,
    )
}

/// The derivatives from their pieces, for any sizes (module docs): the rows `J`, `M⁻¹ Jᵀ`,
/// `M⁻¹`, `Y = −M⁻¹ ∂F/∂x` and `∂G/∂x` (Baumgarte terms included), each pair along `q` then
/// `ν`. Refused where the rows are redundant.
pub fn assemble_derivatives<NV: Dim, NC: Dim>(
    jacobian: &OMatrix<f64, NC, NV>,
    response: &OMatrix<f64, NV, NC>,
    torque_response: OMatrix<f64, NV, NV>,
    y: (OMatrix<f64, NV, NV>, OMatrix<f64, NV, NV>),
    g: (OMatrix<f64, NC, NV>, OMatrix<f64, NC, NV>),
) -> Result<ConstrainedDerivatives<NV, NC>, ContactError>
where
    DefaultAllocator:
        Allocator<NC, NC> + Allocator<NC, NV> + Allocator<NV, NC> + Allocator<NV, NV> + Allocator<NC>,
{
    let delassus = dense::delassus(jacobian, response);
    assemble(jacobian, response, delassus, torque_response, y, g)
}

/// [`assemble_derivatives`] with the Delassus matrix `delassus` (`K = J M⁻¹ Jᵀ`) given.
fn assemble<NV: Dim, NC: Dim>(
    jacobian: &OMatrix<f64, NC, NV>,
    response: &OMatrix<f64, NV, NC>,
    delassus: OMatrix<f64, NC, NC>,
    torque_response: OMatrix<f64, NV, NV>,
    (y_q, y_v): (OMatrix<f64, NV, NV>, OMatrix<f64, NV, NV>),
    (g_q, g_v): (OMatrix<f64, NC, NV>, OMatrix<f64, NC, NV>),
) -> Result<ConstrainedDerivatives<NV, NC>, ContactError>
where
    DefaultAllocator:
        Allocator<NC, NC> + Allocator<NC, NV> + Allocator<NV, NC> + Allocator<NV, NV> + Allocator<NC>,
{
    let lower = factor_delassus(delassus, 0.0)?;
    // `X = K⁻¹ (Ġ + J Y)` (`λ̇ = −X`), every column solved with the one factor at once (a solve
    // per column is a chain of dependent operations; together they vectorise across columns),
    // then `ȧ = Y − M⁻¹ Jᵀ X`. The products accumulate in place: the matrices are `NV × NV`, and
    // moving them through temporaries (`y + r x`) was a large share of the work.
    let solved = |rhs: OMatrix<f64, NC, NV>| {
        let mut rows = rhs.transpose();
        dense::solve_rows_in_place(&lower, &mut rows);
        rows.transpose()
    };
    let moved = |mut g: OMatrix<f64, NC, NV>, y: &OMatrix<f64, NV, NV>| {
        add_product(&mut g, 1.0, jacobian, y);
        g
    };
    let accelerated = |mut y: OMatrix<f64, NV, NV>, x: &OMatrix<f64, NC, NV>| {
        add_product(&mut y, -1.0, response, x);
        y
    };
    let x_q = solved(moved(g_q, &y_q));
    let x_v = solved(moved(g_v, &y_v));
    // Along `τ`: `Ġ + J Y = J M⁻¹ = (M⁻¹ Jᵀ)ᵀ`.
    let x_tau = solved(response.transpose());
    Ok(ConstrainedDerivatives {
        acceleration_q: accelerated(y_q, &x_q),
        acceleration_v: accelerated(y_v, &x_v),
        acceleration_tau: accelerated(torque_response, &x_tau),
        forces_q: x_q.map(|x| -x),
        forces_v: x_v.map(|x| -x),
        forces_tau: x_tau.map(|x| -x),
    })
}

/// `c += alpha a b`, column by column of `c`: each step adds a multiple of a column of `a`,
/// contiguous, so the work vectorises along the rows. (nalgebra's `gemm` in place ran slower at
/// these sizes; so did a column of `a` at a time, skipping the columns of zeros a contact's rows
/// have on the other limbs: `b`'s rows are strided.)
fn add_product<R: Dim, K: Dim, C: Dim>(
    c: &mut OMatrix<f64, R, C>,
    alpha: f64,
    a: &OMatrix<f64, R, K>,
    b: &OMatrix<f64, K, C>,
) where
    DefaultAllocator: Allocator<R, C> + Allocator<R, K> + Allocator<K, C>,
{
    let (rows, inner) = (a.nrows(), b.nrows());
    if rows == 0 || inner == 0 {
        return;
    }
    let a = a.as_slice();
    let columns = c.as_mut_slice().chunks_exact_mut(rows);
    for (column, b_column) in columns.zip(b.as_slice().chunks_exact(inner)) {
        for (a_column, &s) in a.chunks_exact(rows).zip(b_column) {
            let s = alpha * s;
            column.iter_mut().zip(a_column).for_each(|(t, &x)| *t += x * s);
        }
    }
}

/// `∂e/∂q` of the point contacts' placement errors, stacked as their rows (module docs).
fn error_derivatives<R: ContactDynamics<NV, NC>, const NV: usize, const NC: usize>(
    t: &R::Trig,
    jacobian: &SMatrix<f64, NC, NV>,
    stabilisation: &Stabilisation<'_>,
) -> Result<SMatrix<f64, NC, NV>, ContactError> {
    let mut rates = *jacobian;
    for (k, row, error) in placement_errors::<R, NV, NC>(t, stabilisation)? {
        if R::CONTACT_REFERENCES[k] != ReferenceFrame::Local {
            continue;
        }
        // `[e]× Ω`: the error is written in axes that turn with the frame.
        let e = error.fixed_rows::<3>(0).into_owned();
        let local = R::contact_local_jacobian(t, k);
        for c in 0..NV {
            let omega = local.fixed_view::<3, 1>(3, c).into_owned();
            let turn = e.cross(&omega);
            for i in 0..3 {
                rates[(row + i, c)] += turn[i];
            }
        }
    }
    Ok(rates)
}

#[cfg(test)]
mod tests {
    use super::add_product;
    use nalgebra::DMatrix;

    #[test]
    fn add_product_is_c_plus_alpha_a_b_for_any_sizes() {
        let entry = |i: usize, j: usize, k: usize| ((i * 7 + j * 3 + k) % 11) as f64 - 5.0;
        for (r, k, c) in [
            (3, 4, 5),
            (12, 18, 18),
            (1, 1, 1),
            (0, 3, 2),
            (3, 0, 2),
            (4, 2, 0),
        ] {
            let a = DMatrix::from_fn(r, k, |i, j| entry(i, j, 1));
            let b = DMatrix::from_fn(k, c, |i, j| entry(i, j, 2));
            let start = DMatrix::from_fn(r, c, |i, j| entry(i, j, 3));
            let mut sum = start.clone();
            add_product(&mut sum, -0.5, &a, &b);
            assert_eq!(sum, &start - &a * &b * 0.5, "{r} × {k} × {c}");
        }
    }
}
