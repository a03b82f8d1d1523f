//! Fixed-step classical Runge–Kutta (RK4) over any state with `x + h·k`.

/// A state an explicit integrator can step.
pub trait RkState: Copy {
    /// `self + h · k`.
    fn axpy(&self, h: f64, k: &Self) -> Self;
}

/// One RK4 step of `ẋ = f(t, x)`; `f` may fail (then the step fails).
pub fn rk4_step<X: RkState, E>(
    t: f64,
    x: &X,
    h: f64,
    mut f: impl FnMut(f64, &X) -> Result<X, E>,
) -> Result<X, E> {
    let k1 = f(t, x)?;
    let k2 = f(t + 0.5 * h, &x.axpy(0.5 * h, &k1))?;
    let k3 = f(t + 0.5 * h, &x.axpy(0.5 * h, &k2))?;
    let k4 = f(t + h, &x.axpy(h, &k3))?;
    Ok(x.axpy(h / 6.0, &k1)
        .axpy(h / 3.0, &k2)
        .axpy(h / 3.0, &k3)
        .axpy(h / 6.0, &k4))
}
