//! Free motion without gravity, integrated with RK4 through the generated forward dynamics:
//! kinetic energy `½ q̇ᵀ D q̇` is conserved by the exact flow, so its drift is the integrator's
//! error alone, `O(h⁴)`: halving the step must divide it by about 16. A wrong term in `q̈`
//! (a missing Coriolis part, a transposed inverse) breaks conservation at any step.
//!
//! Gravity is removed by applying `τ = g(q)` (the generated `g`), so `q̈ = −D⁻¹ C q̇`.

use dyngen_generated::{Arm7, Panda, PandaRounded, Ur5};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{ForwardDynamics, JointTrig};

type State<const N: usize> = (SVector<f64, N>, SVector<f64, N>);

fn derivative<R: ForwardDynamics<N, P>, const N: usize, const P: usize>((q, qd): &State<N>) -> State<N> {
    let t = JointTrig::new(q);
    (*qd, R::forward_dynamics(&t, qd, &R::gravity(&t)))
}

/// Classical RK4, written out here so that the test depends on nothing but generated code.
fn rk4<R: ForwardDynamics<N, P>, const N: usize, const P: usize>(x: &State<N>, h: f64) -> State<N> {
    let at = |k: &State<N>, s: f64| (x.0 + k.0 * s, x.1 + k.1 * s);
    let k1 = derivative::<R, N, P>(x);
    let k2 = derivative::<R, N, P>(&at(&k1, h / 2.0));
    let k3 = derivative::<R, N, P>(&at(&k2, h / 2.0));
    let k4 = derivative::<R, N, P>(&at(&k3, h));
    let step = |a: SVector<f64, N>, b, c, d| (a + b * 2.0 + c * 2.0 + d) * (h / 6.0);
    (
        x.0 + step(k1.0, k2.0, k3.0, k4.0),
        x.1 + step(k1.1, k2.1, k3.1, k4.1),
    )
}

fn energy<R: ForwardDynamics<N, P>, const N: usize, const P: usize>((q, qd): &State<N>) -> f64 {
    0.5 * qd.dot(&(R::mass_matrix(&JointTrig::new(q)) * qd))
}

/// Largest `|E(t) − E(0)|` over one second at step `h`.
fn drift<R: ForwardDynamics<N, P>, const N: usize, const P: usize>(start: &State<N>, h: f64) -> f64 {
    let e0 = energy::<R, N, P>(start);
    let mut x = *start;
    let mut worst: f64 = 0.0;
    for _ in 0..(1.0 / h).round() as usize {
        x = rk4::<R, N, P>(&x, h);
        worst = worst.max((energy::<R, N, P>(&x) - e0).abs());
    }
    worst
}

fn fourth_order<R: ForwardDynamics<N, P>, const N: usize, const P: usize>() {
    let q = SVector::<f64, N>::from_fn(|i, _| 0.3 + 0.2 * i as f64);
    let qd = SVector::<f64, N>::from_fn(|i, _| if i % 2 == 0 { 1.5 } else { -1.0 });
    let start = (q, qd);
    let e0 = energy::<R, N, P>(&start);
    let (coarse, fine) = (drift::<R, N, P>(&start, 0.01), drift::<R, N, P>(&start, 0.005));
    let ratio = coarse / fine;
    eprintln!(
        "{}: E = {e0:.4} J, drift {coarse:.3e} (h = 0.01), {fine:.3e} (h = 0.005), ratio {ratio:.1}",
        R::NAME
    );
    assert!(fine < 1e-6 * e0, "{}: energy drifts by {fine:e} of {e0}", R::NAME);
    assert!(
        (12.0..20.0).contains(&ratio),
        "{}: halving h divides the drift by {ratio}, not ~16",
        R::NAME
    );
}

#[test]
fn arm7_free_motion_conserves_energy_to_fourth_order() {
    fourth_order::<Arm7, 7, 70>();
}

#[test]
fn panda_free_motion_conserves_energy_to_fourth_order() {
    fourth_order::<Panda, 7, 70>();
}

#[test]
fn panda_rounded_free_motion_conserves_energy_to_fourth_order() {
    fourth_order::<PandaRounded, 7, 70>();
}

#[test]
fn ur5_free_motion_conserves_energy_to_fourth_order() {
    fourth_order::<Ur5, 6, 60>();
}
