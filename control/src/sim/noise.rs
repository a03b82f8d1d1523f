//! Deterministic Gaussian sensor noise (SplitMix64 + Box–Muller): same seed, same run.

use dyngen_runtime::SplitMix64;
use nalgebra::SVector;

/// Standard deviations of the noise added to each measured quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseConfig {
    /// On every joint position (rad).
    pub q: f64,
    /// On every joint velocity (rad/s).
    pub qd: f64,
    /// On every component of the measured force (N).
    pub force: f64,
}

impl NoiseConfig {
    /// σ = 1e-4 rad, 1e-3 rad/s, 0.05 N.
    pub const REFERENCE: NoiseConfig = NoiseConfig {
        q: 1e-4,
        qd: 1e-3,
        force: 0.05,
    };
}

/// A small deterministic normal generator.
#[derive(Clone, Debug)]
pub struct Gaussian {
    rng: SplitMix64,
    spare: Option<f64>,
}

impl Gaussian {
    pub fn new(seed: u64) -> Self {
        Gaussian {
            rng: SplitMix64::new(seed),
            spare: None,
        }
    }

    /// A standard normal sample.
    pub fn sample(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        // Uniform in (0, 1]: never 0, so the logarithm below is finite.
        let mut open_unit = || ((self.rng.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64;
        let (u1, u2) = (open_unit(), open_unit());
        let rad = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (2.0 * std::f64::consts::PI * u2).sin_cos();
        self.spare = Some(rad * s);
        rad * c
    }

    /// A vector of independent samples with standard deviation `sigma`.
    pub fn vector<const D: usize>(&mut self, sigma: f64) -> SVector<f64, D> {
        SVector::from_fn(|_, _| sigma * self.sample())
    }
}
