//! The compiled generated code of `robot::Robot` against one reference file.
//!
//! Pinocchio may number the joints differently from dyngen (both go depth-first, but may visit
//! children in another order), so every reference value is first permuted into dyngen's joint
//! order by joint name. The error of a quantity at a state is `max |generated − reference| /
//! max(1, max |reference|)` (`dyngen_testkit::relative_error`, the measure of the fixture tests);
//! the result is its maximum over the states.

use crate::robot::{self, Robot};
use dyngen_runtime::{
    BaseParameters, DynamicsDerivatives, ForwardDynamics, JointTrig, Kinematics, Regressors, RobotDynamics,
};
use nalgebra::{DMatrix, SMatrix, SVector};
use serde_json::{json, Map, Value};

const N: usize = robot::DOF;
const BODY: usize = dyngen_runtime::PARAMETERS_PER_BODY;

fn numbers(v: &Value, what: &str) -> Result<Vec<f64>, String> {
    v.as_array()
        .ok_or_else(|| format!("{what}: not an array"))?
        .iter()
        .map(|x| x.as_f64().ok_or_else(|| format!("{what}: not a number")))
        .collect()
}

fn matrix(v: &Value, what: &str) -> Result<DMatrix<f64>, String> {
    let rows = v
        .as_array()
        .ok_or_else(|| format!("{what}: not an array of rows"))?
        .iter()
        .map(|r| numbers(r, what))
        .collect::<Result<Vec<_>, _>>()?;
    let cols = rows.first().map_or(0, Vec::len);
    Ok(DMatrix::from_fn(rows.len(), cols, |i, j| rows[i][j]))
}

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn relative_error(actual: &DMatrix<f64>, expected: &DMatrix<f64>) -> f64 {
    if actual.shape() != expected.shape() {
        return f64::INFINITY;
    }
    (actual - expected).amax() / expected.amax().max(1.0)
}

/// Reference values in Pinocchio's joint order, read in dyngen's.
struct Order {
    /// `of[i]`: the reference index of dyngen's joint `i`.
    of: Vec<usize>,
}

impl Order {
    fn new(reference_names: &[String]) -> Result<Order, String> {
        let ours = Robot::JOINT_NAMES;
        let mut theirs: Vec<&str> = reference_names.iter().map(String::as_str).collect();
        let mut sorted_ours = ours.to_vec();
        theirs.sort_unstable();
        sorted_ours.sort_unstable();
        if theirs != sorted_ours {
            return Err(format!(
                "moving joints differ: dyngen {ours:?}, Pinocchio {reference_names:?}"
            ));
        }
        let of = ours
            .iter()
            .map(|n| reference_names.iter().position(|r| r == n).expect("same set"))
            .collect();
        Ok(Order { of })
    }

    fn vector(&self, v: &[f64]) -> SVector<f64, N> {
        SVector::from_fn(|i, _| v[self.of[i]])
    }

    /// Rows and columns permuted (joint-by-joint matrices).
    fn square(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        DMatrix::from_fn(N, N, |i, j| m[(self.of[i], self.of[j])])
    }

    /// Columns permuted (Jacobians).
    fn columns(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        DMatrix::from_fn(m.nrows(), N, |i, j| m[(i, self.of[j])])
    }

    /// Rows permuted, and the ten columns of each body moved with its joint (regressor).
    fn regressor(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        DMatrix::from_fn(N, N * BODY, |i, j| {
            m[(self.of[i], self.of[j / BODY] * BODY + j % BODY)]
        })
    }

    fn parameters(&self, pi: &[f64]) -> DMatrix<f64> {
        DMatrix::from_fn(N * BODY, 1, |j, _| pi[self.of[j / BODY] * BODY + j % BODY])
    }
}

/// The largest error per quantity, in the order first seen.
#[derive(Default)]
struct Worst(Vec<(&'static str, f64)>);

impl Worst {
    fn record(&mut self, what: &'static str, actual: &DMatrix<f64>, expected: &DMatrix<f64>) {
        let err = relative_error(actual, expected);
        match self.0.iter_mut().find(|(name, _)| *name == what) {
            Some((_, worst)) => *worst = worst.max(err),
            None => self.0.push((what, err)),
        }
    }
}

pub fn run(path: &str) -> Result<Value, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let reference: Value = serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    let names: Vec<String> = reference["joint_names"]
        .as_array()
        .ok_or("joint_names missing")?
        .iter()
        .map(|n| n.as_str().unwrap_or_default().to_owned())
        .collect();
    let order = Order::new(&names)?;
    let mut worst = Worst::default();
    let theta = Robot::parameters();
    // With mimic joints Pinocchio keeps a body per mimic joint: then θ and Y have another layout.
    let pi = numbers(&reference["pi"], "pi")?;
    let same_layout = pi.len() == N * BODY && robot::PARAMETER_COUNT == N * BODY;
    if same_layout {
        worst.record("theta", &dm(&theta), &order.parameters(&pi));
    }
    let theta_b = Robot::base_parameters(&theta);
    let states = reference["states"].as_array().ok_or("states missing")?;
    for s in states {
        let vector = |key: &str| numbers(&s[key], key).map(|v| order.vector(&v));
        let (q, v, a, vr, ar, tau) = (
            vector("q")?,
            vector("v")?,
            vector("a")?,
            vector("vr")?,
            vector("ar")?,
            vector("tau")?,
        );
        let square = |key: &str| matrix(&s[key], key).map(|m| order.square(&m));
        let column = |x: SVector<f64, N>| dm(&x);
        let t = JointTrig::new(&q);

        let ee_rotation = matrix(&s["ee_rotation"], "ee_rotation")?;
        let ee_translation = DMatrix::from_vec(3, 1, numbers(&s["ee_translation"], "ee_translation")?);
        let jacobian = order.columns(&matrix(&s["J"], "J")?);
        let jacobian_dot = order.columns(&matrix(&s["Jdot"], "Jdot")?);
        let pose = Robot::forward_kinematics(&t);
        worst.record("ee pose", &dm(&pose.rotation), &ee_rotation);
        worst.record("ee pose", &dm(&pose.translation), &ee_translation);
        worst.record("J", &dm(&Robot::jacobian(&t)), &jacobian);
        worst.record("J̇", &dm(&Robot::jacobian_dot(&t, &v)), &jacobian_dot);
        // The fused function a control tick calls computes the same three from shared transforms.
        let (pose, j, jd) = Robot::kinematics(&t, &v);
        let fused = "kinematics (pose, J, J̇)";
        worst.record(fused, &dm(&pose.rotation), &ee_rotation);
        worst.record(fused, &dm(&pose.translation), &ee_translation);
        worst.record(fused, &dm(&j), &jacobian);
        worst.record(fused, &dm(&jd), &jacobian_dot);
        worst.record("D", &dm(&Robot::mass_matrix(&t)), &square("D")?);
        worst.record("C", &dm(&Robot::coriolis_matrix(&t, &v)), &square("C")?);
        worst.record("g", &dm(&Robot::gravity(&t)), &column(vector("g")?));
        worst.record("τ", &dm(&Robot::inverse_dynamics(&t, &v, &a)), &column(tau));
        worst.record(
            "Slotine–Li τ",
            &dm(&Robot::slotine_li(&t, &v, &vr, &ar)),
            &column(vector("tau_ref")?),
        );
        if same_layout {
            worst.record(
                "Y",
                &dm(&Robot::regressor(&t, &v, &v, &a)),
                &order.regressor(&matrix(&s["Y"], "Y")?),
            );
        }
        worst.record(
            "Y_b θ_b",
            &dm(&(Robot::base_regressor(&t, &v, &v, &a) * theta_b)),
            &column(tau),
        );
        // The torque-form regressors (identification's), emitted as functions of their own.
        if same_layout {
            worst.record(
                "torque-form Y",
                &dm(&Robot::torque_regressor(&t, &v, &a)),
                &order.regressor(&matrix(&s["Y"], "Y")?),
            );
        }
        worst.record(
            "torque-form Y_b θ_b",
            &dm(&(Robot::base_torque_regressor(&t, &v, &a) * theta_b)),
            &column(tau),
        );
        worst.record(
            "FD",
            &dm(&Robot::forward_dynamics(&t, &v, &tau)),
            &column(vector("aba")?),
        );
        worst.record("D⁻¹", &dm(&Robot::mass_matrix_inverse(&t)), &square("Minv")?);
        let (dq, dv) = Robot::inverse_dynamics_derivatives(&t, &v, &a);
        worst.record("∂τ/∂q", &dm(&dq), &square("dtau_dq")?);
        worst.record("∂τ/∂q̇", &dm(&dv), &square("dtau_dv")?);
        let (dq, dv) = Robot::forward_dynamics_derivatives(&t, &v, &tau);
        worst.record("∂q̈/∂q", &dm(&dq), &square("dqdd_dq")?);
        worst.record("∂q̈/∂q̇", &dm(&dv), &square("dqdd_dv")?);
    }
    let mut errors = Map::new();
    for (name, err) in worst.0 {
        errors.insert(name.to_owned(), json!(err));
    }
    Ok(json!({
        "states": states.len(),
        "same_parameter_layout": same_layout,
        "max_relative_error": errors,
    }))
}
