//! Periodic finite-Fourier-series joint trajectories (Swevers et al. 1997), scaled into the
//! joint limits.
//!
//! Joint `j`, base angular frequency `ω = 2π f`, harmonics `l = 1..L`:
//!
//! ```text
//! q_j(t)  = q0_j + Σ_l  a_jl/(ω l) sin(ω l t) − b_jl/(ω l) cos(ω l t)
//! q̇_j(t) =        Σ_l  a_jl cos(ω l t) + b_jl sin(ω l t)
//! q̈_j(t) =        Σ_l −a_jl ω l sin(ω l t) + b_jl ω l cos(ω l t)
//! ```
//!
//! Periodic (so a measurement can average periods and start anywhere), band-limited to
//! `L·f` (so a low-pass filter above that band leaves it intact), and analytic in `q̇`, `q̈`.
//! `q − q0`, `q̇` and `q̈` are linear in the coefficients, so a trajectory is fitted into the
//! limits by scaling each joint's coefficients by one factor: the largest that keeps position,
//! velocity and acceleration within their limits (times a margin), on a dense grid.

use dyngen_model::model::{JointKind, Model};
use std::f64::consts::PI;

/// Joint limits an excitation must respect.
#[derive(Clone, Debug, PartialEq)]
pub struct TrajectoryLimits {
    /// Lowest and highest position per joint.
    pub position: Vec<(f64, f64)>,
    /// Largest speed per joint.
    pub velocity: Vec<f64>,
    /// Largest acceleration per joint.
    pub acceleration: Vec<f64>,
}

/// Descriptions (URDF and dyngen YAML) have no acceleration limits; without one given, a
/// joint may accelerate to this many times its velocity limit per second (e.g. 1.5 rad/s →
/// 4.5 rad/s², reached in a third of a second: the pace of industrial arms' normal motion).
pub const DEFAULT_ACCELERATION_PER_VELOCITY: f64 = 3.0;

/// Continuous joints (no position limits) move within ±π; prismatic joints without limits ±0.5 m.
const UNLIMITED_REVOLUTE: (f64, f64) = (-PI, PI);
const UNLIMITED_PRISMATIC: (f64, f64) = (-0.5, 0.5);
/// Speed of a joint whose description has no velocity limit (rad/s or m/s).
const UNLIMITED_VELOCITY: f64 = 2.0;

impl TrajectoryLimits {
    /// The description's limits, with accelerations of `acceleration_per_velocity` × the
    /// velocity limit (see [`DEFAULT_ACCELERATION_PER_VELOCITY`]).
    pub fn from_model(model: &Model, acceleration_per_velocity: f64) -> TrajectoryLimits {
        let mut limits = TrajectoryLimits {
            position: Vec::new(),
            velocity: Vec::new(),
            acceleration: Vec::new(),
        };
        for joint in model.joints() {
            let (position, velocity) = match (joint.limits, joint.kind) {
                (Some(l), _) if l.velocity > 0.0 => ((l.lower, l.upper), l.velocity),
                (Some(l), _) => ((l.lower, l.upper), UNLIMITED_VELOCITY),
                (None, JointKind::Revolute) => (UNLIMITED_REVOLUTE, UNLIMITED_VELOCITY),
                (None, JointKind::Prismatic) => (UNLIMITED_PRISMATIC, UNLIMITED_VELOCITY),
            };
            limits.position.push(position);
            limits.velocity.push(velocity);
            limits.acceleration.push(velocity * acceleration_per_velocity);
        }
        limits
    }
}

/// A finite Fourier series per joint.
#[derive(Clone, Debug, PartialEq)]
pub struct FourierTrajectory {
    /// Base frequency `f` (Hz); the period is `1/f`.
    pub base_frequency: f64,
    /// Offset `q0` per joint.
    pub offsets: Vec<f64>,
    /// `a[j][l]`, `b[j][l]`: velocity amplitudes of harmonic `l + 1`.
    pub a: Vec<Vec<f64>>,
    pub b: Vec<Vec<f64>>,
}

/// Position, velocity and acceleration of every joint at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSample {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
}

/// Fraction of each limit a scaled trajectory uses (the dense grid may miss a peak slightly).
pub(crate) const LIMIT_MARGIN: f64 = 0.95;
/// Grid points per period and harmonic when scaling into the limits: the highest harmonic is
/// sampled 64 times per its period, so a peak between points is missed by at most
/// `1 − cos(π/64) ≈ 0.1%`, well inside [`LIMIT_MARGIN`].
const GRID_PER_HARMONIC: usize = 64;

impl FourierTrajectory {
    pub fn dof(&self) -> usize {
        self.offsets.len()
    }

    pub fn harmonics(&self) -> usize {
        self.a.first().map_or(0, Vec::len)
    }

    pub fn period(&self) -> f64 {
        1.0 / self.base_frequency
    }

    /// Joint `j` at time `t`: (q, q̇, q̈).
    pub fn joint_at(&self, j: usize, t: f64) -> (f64, f64, f64) {
        let w = 2.0 * PI * self.base_frequency;
        let (mut q, mut qd, mut qdd) = (self.offsets[j], 0.0, 0.0);
        for (l, (&a, &b)) in self.a[j].iter().zip(&self.b[j]).enumerate() {
            let wl = w * (l + 1) as f64;
            let (s, c) = (wl * t).sin_cos();
            q += a / wl * s - b / wl * c;
            qd += a * c + b * s;
            qdd += -a * wl * s + b * wl * c;
        }
        (q, qd, qdd)
    }

    /// Every joint at time `t`.
    pub fn at(&self, t: f64) -> JointSample {
        let mut s = JointSample {
            q: Vec::with_capacity(self.dof()),
            qd: Vec::with_capacity(self.dof()),
            qdd: Vec::with_capacity(self.dof()),
        };
        for j in 0..self.dof() {
            let (q, qd, qdd) = self.joint_at(j, t);
            s.q.push(q);
            s.qd.push(qd);
            s.qdd.push(qdd);
        }
        s
    }

    /// Largest |q − q0|, |q̇|, |q̈| of joint `j` over a period (dense grid).
    fn peaks(&self, j: usize) -> (f64, f64, f64) {
        let points = GRID_PER_HARMONIC * self.harmonics().max(1);
        let mut peaks = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..points {
            let t = self.period() * k as f64 / points as f64;
            let (q, qd, qdd) = self.joint_at(j, t);
            peaks.0 = peaks.0.max((q - self.offsets[j]).abs());
            peaks.1 = peaks.1.max(qd.abs());
            peaks.2 = peaks.2.max(qdd.abs());
        }
        peaks
    }

    /// Centres every joint in its position range and scales its coefficients so that its
    /// binding limit (position, velocity or acceleration) is reached at 95% of it.
    pub fn fit_into(&mut self, limits: &TrajectoryLimits) {
        let centre: Vec<f64> = limits.position.iter().map(|(lo, hi)| 0.5 * (lo + hi)).collect();
        self.fit_around(limits, &centre);
    }

    /// [`FourierTrajectory::fit_into`] around the posture `centre` (within the position
    /// ranges) instead of the ranges' middle: the excursion is limited by the nearer end.
    pub fn fit_around(&mut self, limits: &TrajectoryLimits, centre: &[f64]) {
        for (j, &c) in centre.iter().enumerate().take(self.dof()) {
            let (lo, hi) = limits.position[j];
            self.offsets[j] = c;
            let (dq, v, a) = self.peaks(j);
            let ratio = |limit: f64, peak: f64| if peak > 0.0 { limit / peak } else { f64::INFINITY };
            let room = (hi - c).min(c - lo).max(0.0);
            let scale = LIMIT_MARGIN
                * ratio(room, dq)
                    .min(ratio(limits.velocity[j], v))
                    .min(ratio(limits.acceleration[j], a));
            if scale.is_finite() {
                self.a[j]
                    .iter_mut()
                    .chain(self.b[j].iter_mut())
                    .for_each(|c| *c *= scale);
            }
        }
    }

    /// The same motion with every excursion from the offsets (and so every velocity and
    /// acceleration) `s` times as large.
    pub fn scaled(&self, s: f64) -> FourierTrajectory {
        let mut t = self.clone();
        t.a.iter_mut()
            .chain(t.b.iter_mut())
            .flatten()
            .for_each(|c| *c *= s);
        t
    }

    /// The coefficients as one vector (`a` then `b`, joint after joint), for optimisers.
    pub fn coefficients(&self) -> Vec<f64> {
        self.a
            .iter()
            .zip(&self.b)
            .flat_map(|(a, b)| a.iter().chain(b.iter()).copied())
            .collect()
    }

    /// The trajectory with the coefficients of [`FourierTrajectory::coefficients`].
    pub fn with_coefficients(&self, x: &[f64]) -> FourierTrajectory {
        let l = self.harmonics();
        let mut t = self.clone();
        for j in 0..self.dof() {
            let block = &x[2 * l * j..2 * l * (j + 1)];
            t.a[j] = block[..l].to_vec();
            t.b[j] = block[l..].to_vec();
        }
        t
    }

    /// A trajectory with coefficients uniform in ±1 (before scaling), the same for the same seed.
    pub fn random(dof: usize, harmonics: usize, base_frequency: f64, seed: u64) -> FourierTrajectory {
        let mut rng = dyngen_runtime::SplitMix64::new(seed);
        let mut draw = || {
            (0..harmonics)
                .map(|_| rng.uniform((-1.0, 1.0)))
                .collect::<Vec<f64>>()
        };
        let (a, b): (Vec<_>, Vec<_>) = (0..dof).map(|_| (draw(), draw())).unzip();
        FourierTrajectory {
            base_frequency,
            offsets: vec![0.0; dof],
            a,
            b,
        }
    }

    /// Whether every joint stays within `limits` (exactly, no margin) at the times `times`;
    /// the first violation as (joint, what, value, limit) otherwise.
    pub fn check_limits(
        &self,
        limits: &TrajectoryLimits,
        times: &[f64],
    ) -> Result<(), (usize, &'static str, f64, f64)> {
        for &t in times {
            for j in 0..self.dof() {
                let (q, qd, qdd) = self.joint_at(j, t);
                let (lo, hi) = limits.position[j];
                if q < lo || q > hi {
                    return Err((j, "position", q, if q < lo { lo } else { hi }));
                }
                if qd.abs() > limits.velocity[j] {
                    return Err((j, "velocity", qd, limits.velocity[j]));
                }
                if qdd.abs() > limits.acceleration[j] {
                    return Err((j, "acceleration", qdd, limits.acceleration[j]));
                }
            }
        }
        Ok(())
    }
}
