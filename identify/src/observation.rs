//! The base regressor stacked over samples, in torque form (`v = q̇`, `a = q̈`, so that
//! `Y_b θ_b = τ`): from the generic numeric dynamics ([`BaseModel`]), so identification works
//! for any description, or from a compiled robot's generated `Y_b` ([`Compiled`]), several
//! times faster, when the robot is compiled in.
//!
//! Rows are sample-major: row `k·n + j` is joint `j` at sample `k`.

use crate::data::Samples;
use crate::differentiate::{differences, filtfilt, padding, uniform_rate};
use crate::error::IdentifyError;
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::Model;
use dyngen_runtime::{BaseParameters, JointTrig};
use nalgebra::{DMatrix, DVector, SVector};
use std::marker::PhantomData;

/// Where the torque-form base regressor comes from.
pub trait BaseRegressorSource {
    fn dof(&self) -> usize;
    /// Names of the base parameters, in column order.
    fn base_names(&self) -> Vec<String>;
    /// `Y_b(q, q̇, q̇, q̈)`, n × b.
    fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64>;

    /// The base regressor stacked over `states` (q, q̇, q̈).
    fn stack<'a>(
        &self,
        states: impl ExactSizeIterator<Item = (&'a [f64], &'a [f64], &'a [f64])>,
    ) -> DMatrix<f64>
    where
        Self: Sized,
    {
        let (n, b) = (self.dof(), self.base_names().len());
        let mut w = DMatrix::zeros(states.len() * n, b);
        for (k, (q, qd, qdd)) in states.enumerate() {
            w.view_mut((k * n, 0), (n, b))
                .copy_from(&self.base_regressor(q, qd, qdd));
        }
        w
    }
}

/// A compiled (generated) robot `R` as a regressor source: its flattened `base_regressor`.
pub struct Compiled<R, const N: usize, const P: usize, const B: usize>(PhantomData<R>);

impl<R, const N: usize, const P: usize, const B: usize> Default for Compiled<R, N, P, B> {
    fn default() -> Self {
        Compiled(PhantomData)
    }
}

impl<R: BaseParameters<N, P, B>, const N: usize, const P: usize, const B: usize> BaseRegressorSource
    for Compiled<R, N, P, B>
{
    fn dof(&self) -> usize {
        N
    }

    fn base_names(&self) -> Vec<String> {
        R::BASE_PARAMETER_NAMES.iter().map(|s| s.to_string()).collect()
    }

    fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64> {
        let (q, qd, qdd) = (
            SVector::<f64, N>::from_column_slice(q),
            SVector::<f64, N>::from_column_slice(qd),
            SVector::<f64, N>::from_column_slice(qdd),
        );
        let y = R::base_torque_regressor(&JointTrig::new(&q), &qd, &qdd);
        DMatrix::from_column_slice(N, B, y.as_slice())
    }
}

/// A model with its base parameters: what the regressor of an identification multiplies.
pub struct BaseModel<'m> {
    pub model: &'m Model,
    pub base: BaseParameterSet,
    dynamics: NumericDynamics<'m>,
}

impl<'m> BaseModel<'m> {
    pub fn new(model: &'m Model) -> BaseModel<'m> {
        BaseModel {
            model,
            base: BaseParameterSet::compute(model),
            dynamics: NumericDynamics::new(model),
        }
    }

    pub fn base_count(&self) -> usize {
        self.base.count()
    }
}

impl BaseRegressorSource for BaseModel<'_> {
    fn dof(&self) -> usize {
        self.model.dof()
    }

    fn base_names(&self) -> Vec<String> {
        self.base.names.clone()
    }

    fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DMatrix<f64> {
        let y = self.dynamics.regressor(q, qd, qd, qdd);
        self.base.base_regressor(&y)
    }
}

/// Samples with velocities and accelerations, ready to stack.
#[derive(Clone, Debug, PartialEq)]
pub struct Prepared {
    pub q: Vec<Vec<f64>>,
    pub qd: Vec<Vec<f64>>,
    pub qdd: Vec<Vec<f64>>,
    pub tau: Vec<Vec<f64>>,
    /// Index in the original samples of each kept sample.
    pub kept: Vec<usize>,
    /// Whether q̇, q̈ were computed (filter and differences) rather than given.
    pub differentiated: bool,
}

/// Completes `samples` (which must have torques): missing `q̇`/`q̈` are computed
/// (zero-phase low-pass filter and central differences, cutoff `cutoff` Hz), and then the filter's end transients are
/// dropped. Given `q̇`/`q̈` are used as they are.
pub fn prepare(samples: &Samples, cutoff: f64) -> Result<Prepared, IdentifyError> {
    let Some(tau) = &samples.tau else {
        return Err(IdentifyError::data(
            "the data has no torque columns (tau[<joint>])",
        ));
    };
    let motion = motion(samples, cutoff)?;
    let pick = |v: &Vec<Vec<f64>>| motion.kept.iter().map(|&k| v[k].clone()).collect::<Vec<_>>();
    Ok(Prepared {
        q: pick(&samples.q),
        tau: pick(tau),
        qd: motion.qd,
        qdd: motion.qdd,
        kept: motion.kept,
        differentiated: motion.differentiated,
    })
}

/// Velocities and accelerations of the samples kept.
pub(crate) struct Motion {
    pub qd: Vec<Vec<f64>>,
    pub qdd: Vec<Vec<f64>>,
    /// Index in the samples of each one kept.
    pub kept: Vec<usize>,
    pub differentiated: bool,
}

/// `q̇` and `q̈` of `samples`, given or computed as [`prepare`] says.
pub(crate) fn motion(samples: &Samples, cutoff: f64) -> Result<Motion, IdentifyError> {
    if let (Some(qd), Some(qdd)) = (&samples.qd, &samples.qdd) {
        return Ok(Motion {
            qd: qd.clone(),
            qdd: qdd.clone(),
            kept: (0..samples.len()).collect(),
            differentiated: false,
        });
    }
    let rate = uniform_rate(&samples.time, &samples.lines)?;
    if !(cutoff > 0.0 && cutoff < 0.5 * rate) {
        return Err(IdentifyError::data(format!(
            "filter cutoff {cutoff} Hz must lie between 0 and half the sampling rate ({} Hz)",
            0.5 * rate
        )));
    }
    let n = samples.q.first().map_or(0, Vec::len);
    let mut qd = vec![vec![0.0; n]; samples.len()];
    let mut qdd = vec![vec![0.0; n]; samples.len()];
    for j in 0..n {
        let x: Vec<f64> = samples.q.iter().map(|r| r[j]).collect();
        let (d1, d2) = differences(&samples.time, &filtfilt(&x, rate, cutoff));
        for k in 0..samples.len() {
            qd[k][j] = d1[k];
            qdd[k][j] = d2[k];
        }
    }
    if let Some(given) = &samples.qd {
        qd = given.clone();
    }
    let pad = padding(rate, cutoff);
    if samples.len() <= 2 * pad {
        return Err(IdentifyError::data(format!(
            "{} samples: the filter's transients take {pad} at each end; give more samples or q̇ and q̈",
            samples.len()
        )));
    }
    let kept: Vec<usize> = (pad..samples.len() - pad).collect();
    let pick = |v: &Vec<Vec<f64>>| kept.iter().map(|&k| v[k].clone()).collect::<Vec<_>>();
    Ok(Motion {
        qd: pick(&qd),
        qdd: pick(&qdd),
        kept,
        differentiated: true,
    })
}

/// The positions of the samples `kept`, through the zero-phase low-pass filter that
/// [`prepare`] differentiates when the data has no velocities (as they are, when it has).
pub(crate) fn filtered_positions(
    samples: &Samples,
    kept: &[usize],
    cutoff: f64,
) -> Result<Vec<Vec<f64>>, IdentifyError> {
    if samples.qd.is_some() {
        return Ok(kept.iter().map(|&k| samples.q[k].clone()).collect());
    }
    let rate = uniform_rate(&samples.time, &samples.lines)?;
    let n = samples.q.first().map_or(0, Vec::len);
    let columns: Vec<Vec<f64>> = (0..n)
        .map(|j| filtfilt(&samples.q.iter().map(|r| r[j]).collect::<Vec<_>>(), rate, cutoff))
        .collect();
    Ok(kept
        .iter()
        .map(|&k| columns.iter().map(|c| c[k]).collect())
        .collect())
}

impl Prepared {
    /// The stacked base regressor and torque vector.
    pub fn stack(&self, base: &impl BaseRegressorSource) -> (DMatrix<f64>, DVector<f64>) {
        let states = (0..self.q.len()).map(|k| (&self.q[k][..], &self.qd[k][..], &self.qdd[k][..]));
        let w = base.stack(states);
        let tau = DVector::from_iterator(w.nrows(), self.tau.iter().flatten().copied());
        (w, tau)
    }
}
