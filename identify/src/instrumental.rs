//! Instrumental variables: `(Zᵀ Σ⁻¹ W) θ_b = Zᵀ Σ⁻¹ τ`, the estimator of IDIM-IV.
//!
//! Least squares on `W θ_b ≈ τ` are biased when `W` itself is noisy: accelerations
//! differentiated twice from encoder counts put errors in the variables, which correlate with
//! `W`'s own columns (the fit shrinks what multiplies them). Multiplying by instruments `Z`
//! that follow the same motion but carry none of its noise (the base regressor of a
//! simulation, [`crate::fixed_point`]) removes the correlation, and with it the bias; the
//! noise is then only in the variance.
//!
//! Weighting and noise as the least squares' ([`crate::least_squares`]): each joint's rows
//! weighted by `1/σ_j²`, the `σ_j` estimated from the residuals `τ − W θ_b` over the joint's
//! degrees of freedom (`N` less its share `w_j tr(A⁻¹ Z_jᵀ W_j)` of the projection's trace);
//! the iteration that rebuilds the instruments re-estimates them with the parameters
//! ([`crate::fixed_point`]). Columns scaled to unit norm (`W`'s and `Z`'s each their own: the
//! estimate does not depend on the instruments' scale).
//!
//! Covariance, the usual sandwich: `s² (Zᵀ Σ⁻¹ W)⁻¹ (Zᵀ Σ⁻¹ Z) (Wᵀ Σ⁻¹ Z)⁻¹`, `s²` the weighted
//! residual variance; with `Z = W` it is the least squares'.

use crate::error::IdentifyError;
use crate::least_squares::{
    floored_noise, relative_change, scaled_condition_number, BaseEstimate, NOISE_SETTLED,
};
use nalgebra::{DMatrix, DVector};

/// The measured side of the instrumental-variable equations, prepared once for every set of
/// instruments: `W`'s rows per joint, column-scaled, and the torques.
pub(crate) struct Measured {
    n: usize,
    names: Vec<String>,
    norms: Vec<f64>,
    /// Per joint: its rows of the scaled `W`, its torques.
    joints: Vec<(DMatrix<f64>, DVector<f64>)>,
    condition_number: f64,
    torque_rms: Vec<f64>,
}

/// One joint's products of its instruments `Z_j` with its rows `W_j`, with themselves and with
/// its torques `τ_j`, in scaled columns.
struct JointProducts {
    zw: DMatrix<f64>,
    zz: DMatrix<f64>,
    z_tau: DVector<f64>,
}

/// Column norms of `m`, each at least the smallest positive number.
fn column_norms(m: &DMatrix<f64>) -> Vec<f64> {
    m.column_iter().map(|c| c.norm().max(f64::MIN_POSITIVE)).collect()
}

/// The rows of joint `j` of the stacked `m` (rows sample-major over `n` joints), each column
/// divided by `norms`.
fn joint_rows(m: &DMatrix<f64>, j: usize, n: usize, norms: &[f64]) -> DMatrix<f64> {
    let rows = m.nrows() / n;
    DMatrix::from_fn(rows, m.ncols(), |r, c| m[(r * n + j, c)] / norms[c])
}

impl Measured {
    /// `W θ ≈ τ` (rows sample-major over `n` joints), the parameters named `names`; an error
    /// naming a parameter `W` cannot determine.
    pub fn new(
        w: &DMatrix<f64>,
        tau: &DVector<f64>,
        n: usize,
        names: &[String],
    ) -> Result<Measured, IdentifyError> {
        let norms = column_norms(w);
        let joints: Vec<(DMatrix<f64>, DVector<f64>)> = (0..n)
            .map(|j| {
                let wj = joint_rows(w, j, n, &norms);
                let tj = DVector::from_iterator(wj.nrows(), (j..tau.len()).step_by(n).map(|r| tau[r]));
                (wj, tj)
            })
            .collect();
        let gram = joints
            .iter()
            .fold(DMatrix::zeros(w.ncols(), w.ncols()), |acc, (wj, _)| {
                acc + wj.tr_mul(wj)
            });
        let condition_number = scaled_condition_number(&gram, names)?;
        let torque_rms = joints
            .iter()
            .map(|(_, t)| (t.norm_squared() / t.len().max(1) as f64).sqrt())
            .collect();
        Ok(Measured {
            n,
            names: names.to_vec(),
            norms,
            joints,
            condition_number,
            torque_rms,
        })
    }

    /// The estimate with instruments `z` (`W`'s shape), each joint weighted by `1/noise_j²`,
    /// and the noise its residuals show (`noise_settled` when that is `noise` to
    /// [`NOISE_SETTLED`]); the outer iteration re-estimates the noise with the parameters.
    pub fn estimate(&self, z: &DMatrix<f64>, noise: &[f64]) -> Result<BaseEstimate, IdentifyError> {
        let (n, b) = (self.n, self.norms.len());
        let z_norms = column_norms(z);
        let products: Vec<JointProducts> = self
            .joints
            .iter()
            .enumerate()
            .map(|(j, (wj, tj))| {
                let zj = joint_rows(z, j, n, &z_norms);
                JointProducts {
                    zw: zj.tr_mul(wj),
                    zz: zj.tr_mul(&zj),
                    z_tau: zj.tr_mul(tj),
                }
            })
            .collect();
        // The instruments must determine every parameter, as the measured regressor must.
        let zz = products.iter().fold(DMatrix::zeros(b, b), |acc, p| acc + &p.zz);
        scaled_condition_number(&zz, &self.names)?;
        let weights: Vec<f64> = noise.iter().map(|s| s.powi(-2)).collect();
        let weighted = |pick: &dyn Fn(&JointProducts) -> DMatrix<f64>| {
            products
                .iter()
                .zip(&weights)
                .map(|(p, w)| pick(p) * *w)
                .reduce(|acc, m| acc + m)
                .expect("a robot has joints")
        };
        let a = weighted(&|p| p.zw.clone());
        let rhs = weighted(&|p| DMatrix::from_column_slice(b, 1, p.z_tau.as_slice()));
        let a_inv = a.try_inverse().ok_or_else(|| {
            IdentifyError::Unidentifiable(
                "the instruments do not determine the parameters (Zᵀ W is singular): the simulated \
                 motion does not follow the measured one"
                    .into(),
            )
        })?;
        let x = (&a_inv * rhs).column(0).into_owned();
        let squares: Vec<f64> = self
            .joints
            .iter()
            .map(|(wj, tj)| (tj - wj * &x).norm_squared())
            .collect();
        // σ_j² = ‖r_j‖² over the joint's degrees of freedom, N less its share of the trace.
        let raw: Vec<f64> = (0..n)
            .map(|j| {
                let samples = self.joints[j].1.len() as f64;
                let leverage = (&a_inv * &products[j].zw).trace() * weights[j];
                (squares[j] / (samples - leverage).max(1.0)).sqrt()
            })
            .collect();
        let next = floored_noise(&raw, &self.torque_rms);
        let rows: usize = self.joints.iter().map(|(wj, _)| wj.nrows()).sum();
        let s2 = squares.iter().zip(&weights).map(|(r, w)| r * w).sum::<f64>() / (rows - b) as f64;
        let s2 = if s2 > 0.0 { s2 } else { 1.0 };
        let middle = weighted(&|p| p.zz.clone());
        let covariance = (&a_inv * middle * a_inv.transpose()) * s2;
        let covariance = (&covariance + covariance.transpose()) * 0.5;
        let information = covariance
            .clone()
            .cholesky()
            .map(|c| c.inverse())
            .ok_or_else(|| {
                IdentifyError::Unidentifiable(
                    "the instrumental-variable covariance is not positive definite: the instruments do \
                 not determine every parameter"
                        .into(),
                )
            })?;
        Ok(BaseEstimate {
            names: self.names.clone(),
            theta_b: (0..b).map(|k| x[k] / self.norms[k]).collect(),
            std_dev: (0..b)
                .map(|k| covariance[(k, k)].sqrt() / self.norms[k])
                .collect(),
            noise_settled: relative_change(&next, noise) <= NOISE_SETTLED,
            joint_noise: next,
            noise_iterations: 1,
            residual_variance: s2,
            information_scaled: information,
            scale: self.norms.iter().map(|s| 1.0 / s).collect(),
            condition_number: self.condition_number,
        })
    }
}
