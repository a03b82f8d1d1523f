//! Each composed function against its straight-line form, in interleaved rounds in one
//! process: `taskset -c 1 cargo run --release -- [ROUNDS]` on an idle machine. Checks first
//! that both forms agree (1e-10 relative), then prints the median ns per call over the rounds.

use dyngen_compare_shapes::{g1_composed, g1_flat, solo12_composed, solo12_flat};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::prelude::*;
use dyngen_runtime::SplitMix64;
use std::hint::black_box;
use std::time::Instant;

const STATES: usize = 32;

/// Random floating states: a configuration with a unit quaternion, a velocity, torques.
fn floating<const N: usize, const NQ: usize, const NV: usize>(
) -> Vec<(FloatingTrig<N>, SVector<f64, NV>, SVector<f64, NV>)> {
    let mut rng = SplitMix64::new(18);
    (0..STATES)
        .map(|_| {
            let mut q = [0.0; NQ];
            q.iter_mut().for_each(|x| *x = rng.uniform((-1.0, 1.0)));
            let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            q[3..7].iter_mut().for_each(|x| *x /= norm);
            let t = FloatingTrig::from_configuration(&q).expect("a unit quaternion");
            let v = SVector::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let tau = SVector::from_fn(|_, _| rng.uniform((-10.0, 10.0)));
            (t, v, tau)
        })
        .collect()
}

/// The median over 21 samples of the ns per call of `f` over every state.
fn time(mut f: impl FnMut()) -> f64 {
    let mut samples: Vec<f64> = (0..21)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_nanos() as f64 / STATES as f64
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[10]
}

fn close(what: &str, a: &[f64], b: &[f64]) {
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let error = a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        error <= 1e-10 * scale,
        "{what}: the two forms differ by {error:e}"
    );
}

/// The rows of one floating robot: (function, straight-line ns, composed ns).
macro_rules! floating_rows {
    ($name:expr, $flat:ty, $composed:ty, $states:expr) => {{
        let states = &$states;
        for (t, v, tau) in states {
            close(
                "ν̇",
                <$composed>::forward_dynamics(t, v, tau).as_slice(),
                <$flat>::forward_dynamics(t, v, tau).as_slice(),
            );
            close(
                "D⁻¹",
                <$composed>::mass_matrix_inverse(t).as_slice(),
                <$flat>::mass_matrix_inverse(t).as_slice(),
            );
            let (cq, cv) = <$composed>::forward_dynamics_derivatives(t, v, tau);
            let (fq, fv) = <$flat>::forward_dynamics_derivatives(t, v, tau);
            close("∂ν̇/∂q", cq.as_slice(), fq.as_slice());
            close("∂ν̇/∂ν", cv.as_slice(), fv.as_slice());
        }
        vec![
            (
                concat!($name, " forward_dynamics"),
                time(|| {
                    states.iter().for_each(|(t, v, tau)| {
                        black_box(<$flat>::forward_dynamics(t, v, tau));
                    })
                }),
                time(|| {
                    states.iter().for_each(|(t, v, tau)| {
                        black_box(<$composed>::forward_dynamics(t, v, tau));
                    })
                }),
            ),
            (
                concat!($name, " mass_matrix_inverse"),
                time(|| {
                    states.iter().for_each(|(t, _, _)| {
                        black_box(<$flat>::mass_matrix_inverse(t));
                    })
                }),
                time(|| {
                    states.iter().for_each(|(t, _, _)| {
                        black_box(<$composed>::mass_matrix_inverse(t));
                    })
                }),
            ),
            (
                concat!($name, " forward_dynamics_derivatives"),
                time(|| {
                    states.iter().for_each(|(t, v, tau)| {
                        black_box(<$flat>::forward_dynamics_derivatives(t, v, tau));
                    })
                }),
                time(|| {
                    states.iter().for_each(|(t, v, tau)| {
                        black_box(<$composed>::forward_dynamics_derivatives(t, v, tau));
                    })
                }),
            ),
        ]
    }};
}

#[cfg(tiago)]
fn tiago_rows() -> Vec<(&'static str, f64, f64)> {
    use dyngen_compare_shapes::{tiago_composed::TiagoComposed, tiago_flat::TiagoFlat};
    let mut rng = SplitMix64::new(18);
    let states: Vec<_> = (0..STATES)
        .map(|_| {
            let q = SVector::<f64, 101>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let v = SVector::<f64, 101>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let tau = SVector::<f64, 101>::from_fn(|_, _| rng.uniform((-10.0, 10.0)));
            (JointTrig::new(&q), v, tau)
        })
        .collect();
    for (t, v, tau) in &states {
        close(
            "ν̇",
            TiagoComposed::forward_dynamics(t, v, tau).as_slice(),
            TiagoFlat::forward_dynamics(t, v, tau).as_slice(),
        );
        close(
            "D⁻¹",
            TiagoComposed::mass_matrix_inverse(t).as_slice(),
            TiagoFlat::mass_matrix_inverse(t).as_slice(),
        );
    }
    vec![
        (
            "tiago_dual forward_dynamics",
            time(|| {
                states.iter().for_each(|(t, v, tau)| {
                    black_box(TiagoFlat::forward_dynamics(t, v, tau));
                })
            }),
            time(|| {
                states.iter().for_each(|(t, v, tau)| {
                    black_box(TiagoComposed::forward_dynamics(t, v, tau));
                })
            }),
        ),
        (
            "tiago_dual mass_matrix_inverse",
            time(|| {
                states.iter().for_each(|(t, _, _)| {
                    black_box(TiagoFlat::mass_matrix_inverse(t));
                })
            }),
            time(|| {
                states.iter().for_each(|(t, _, _)| {
                    black_box(TiagoComposed::mass_matrix_inverse(t));
                })
            }),
        ),
    ]
}

#[cfg(not(tiago))]
fn tiago_rows() -> Vec<(&'static str, f64, f64)> {
    Vec::new()
}

fn main() {
    let rounds: usize = std::env::args().nth(1).map_or(5, |r| r.parse().expect("ROUNDS"));
    let (g1, solo) = (floating::<29, 36, 35>(), floating::<12, 19, 18>());
    let mut all: Vec<(&str, Vec<f64>, Vec<f64>)> = Vec::new();
    for _ in 0..rounds {
        let mut rows = floating_rows!("g1", g1_flat::G1Flat, g1_composed::G1Composed, g1);
        rows.extend(floating_rows!(
            "solo12",
            solo12_flat::Solo12Flat,
            solo12_composed::Solo12Composed,
            solo
        ));
        rows.extend(tiago_rows());
        if all.is_empty() {
            all = rows
                .iter()
                .map(|&(name, _, _)| (name, Vec::new(), Vec::new()))
                .collect();
        }
        for (row, (_, flat, composed)) in all.iter_mut().zip(rows) {
            row.1.push(flat);
            row.2.push(composed);
        }
    }
    let median = |x: &mut Vec<f64>| {
        x.sort_by(f64::total_cmp);
        x[x.len() / 2]
    };
    println!(
        "| function | straight-line ns | composed ns | composed / straight-line |\n|---|---:|---:|---:|"
    );
    for (name, mut flat, mut composed) in all {
        let (f, c) = (median(&mut flat), median(&mut composed));
        println!("| {name} | {f:.0} | {c:.0} | {:.2}× |", c / f);
    }
}
