//! The torque-form observation accumulated instead of stacked: per joint, the Gram matrix
//! `Σ_k y_kjᵀ y_kj` of its regressor rows, `Σ_k y_kjᵀ τ_kj` and `Σ_k τ_kj²`. Everything the
//! weighted least squares needs (the noise of each joint is re-estimated from its own residual
//! sum of squares, and a weighted fit's normal matrix is the weighted sum of the joints'), in
//! `n (b² + b + 1)` numbers whatever the length of the log.
//!
//! Rows are gathered in blocks of [`BLOCK`] samples per joint so that the products run as
//! blocked matrix multiplications, the same as the stacked path's.
//!
//! Accuracy: the normal equations lose what the stacked path recovers by refining with the
//! true residual, so a parameter carries a relative error of about `κ² ε` (`κ` the scaled
//! condition number): 10⁻¹¹ for a good excitation (κ ≈ 300), and the residual sums of squares
//! of a joint lose the digits its noise is below its torque (10⁻¹² of them at 1% noise).

use nalgebra::{DMatrix, DMatrixView, DVector};

/// Samples gathered before they are multiplied in.
const BLOCK: usize = 512;

/// Accumulated per-joint normal equations of `Y_b θ_b ≈ τ`.
#[derive(Clone, Debug)]
pub struct NormalEquations {
    n: usize,
    b: usize,
    grams: Vec<DMatrix<f64>>,
    rhs: Vec<DVector<f64>>,
    squares: Vec<f64>,
    samples: usize,
    /// Rows waiting to be multiplied in, per joint, one column per sample (`b × BLOCK`: a
    /// sample's row is written contiguously), with their torques.
    pending: Vec<DMatrix<f64>>,
    pending_tau: Vec<DVector<f64>>,
    filled: usize,
}

impl NormalEquations {
    /// Empty equations of a robot with `n` joints and `b` base parameters.
    pub fn new(n: usize, b: usize) -> NormalEquations {
        NormalEquations {
            n,
            b,
            grams: vec![DMatrix::zeros(b, b); n],
            rhs: vec![DVector::zeros(b); n],
            squares: vec![0.0; n],
            samples: 0,
            pending: vec![DMatrix::zeros(b, BLOCK); n],
            pending_tau: vec![DVector::zeros(BLOCK); n],
            filled: 0,
        }
    }

    /// Adds one sample: its base regressor `y` (`n × b`) and torques `tau`.
    pub fn push(&mut self, y: &DMatrix<f64>, tau: &[f64]) {
        assert_eq!(y.shape(), (self.n, self.b), "regressor of the wrong shape");
        assert_eq!(tau.len(), self.n, "torques of the wrong length");
        for (j, (&t, (pending, pending_tau))) in tau
            .iter()
            .zip(self.pending.iter_mut().zip(&mut self.pending_tau))
            .enumerate()
        {
            pending.column_mut(self.filled).copy_from(&y.row(j).transpose());
            pending_tau[self.filled] = t;
        }
        self.filled += 1;
        self.samples += 1;
        if self.filled == BLOCK {
            self.flush();
        }
    }

    /// Multiplies the pending rows in.
    fn flush(&mut self) {
        let rows = self.filled;
        let b = self.b;
        for j in 0..self.n {
            let data = &self.pending[j].as_slice()[..rows * b];
            let columns = DMatrixView::from_slice(data, b, rows);
            // The same numbers seen as rows × b: the product runs as one blocked matrix
            // multiplication on strides, without a transposed copy.
            let rows_view = DMatrixView::from_slice_with_strides(data, rows, b, b, 1);
            let tau = self.pending_tau[j].rows(0, rows);
            self.grams[j].gemm(1.0, &columns, &rows_view, 1.0);
            self.rhs[j].gemv(1.0, &columns, &tau, 1.0);
            self.squares[j] += tau.norm_squared();
        }
        self.filled = 0;
    }

    /// The equations of a stacked regressor `w` (rows sample-major over `n` joints) and its
    /// torques.
    pub fn from_stacked(w: &DMatrix<f64>, tau: &DVector<f64>, n: usize) -> NormalEquations {
        let (rows, b) = w.shape();
        let samples = rows / n.max(1);
        let mut equations = NormalEquations::new(n, b);
        for j in 0..n {
            let picked: Vec<usize> = (0..samples).map(|k| k * n + j).collect();
            let block = w.select_rows(picked.iter());
            let t = DVector::from_iterator(samples, picked.iter().map(|&r| tau[r]));
            let transposed = block.transpose();
            equations.grams[j] = &transposed * &block;
            equations.rhs[j] = &transposed * &t;
            equations.squares[j] = t.norm_squared();
        }
        equations.samples = samples;
        equations
    }

    /// The finished equations: every pending row multiplied in.
    pub fn finished(mut self) -> NormalEquations {
        if self.filled > 0 {
            self.flush();
        }
        self
    }

    pub fn dof(&self) -> usize {
        self.n
    }

    pub fn parameters(&self) -> usize {
        self.b
    }

    /// Samples added so far.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Joint `j`'s `Σ yᵀy`, `Σ yᵀτ` and `Σ τ²` (pending rows not included until
    /// [`NormalEquations::finished`]).
    pub(crate) fn joint(&self, j: usize) -> (&DMatrix<f64>, &DVector<f64>, f64) {
        (&self.grams[j], &self.rhs[j], self.squares[j])
    }
}
