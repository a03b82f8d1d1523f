//! Robots measured in a closed loop, as a controller's log has them: a 6-axis arm (UR5) with a
//! heavy tool and the 7-axis arm7, each tracking a random excitation with a PD, logged at
//! 200 Hz by encoders (12 bits per turn on the UR5, 14 on arm7: the heavy arm's torques dwarf
//! what 14-bit noise does to its regressor) and torques with noise of 0.5% of the rated
//! torque; and the error measures the estimators are compared by.

use super::{arm7, arm7_joint_values, joint_values};
use dyngen_identify::{
    measure_closed_loop, with_joint_terms, with_payload, BaseEstimate, BaseModel, BaseRegressorSource,
    ClosedLoop, ControlLaw, FourierTrajectory, Logging, Reference, Samples, TrajectoryLimits,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::description::load;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{JointTermValues, Model};
use nalgebra::{DVector, Vector3};
use std::f64::consts::PI;
use std::path::Path;

/// The log's rate (Hz) and length (s).
pub const RATE: f64 = 200.0;
pub const SECONDS: f64 = 10.0;
/// Coulomb friction `f_c tanh(q̇/ε)` with this `ε` (rad/s), in the robot and in its
/// description: a friction that switches sign within an integration step (`sign(q̇)`) makes
/// the simulated robot chatter at every reversal, holding it still with a torque no friction
/// model of a description has; the comparison is then of that, not of the encoders' noise.
pub const COULOMB_SMOOTHING: f64 = 0.01;
/// The controller's bandwidth: a critically damped PD of this natural frequency (Hz) per joint
/// of the real robot.
const BANDWIDTH_HZ: f64 = 5.0;

/// A robot, its description, the controller it runs and what it tracks.
pub struct Case {
    pub truth: Model,
    /// What identification starts from: no tool, joint terms zero (arm7: its armature from a
    /// datasheet, 20% low).
    pub description: Model,
    pub law: ControlLaw,
    pub trajectory: FourierTrajectory,
    pub torque_noise: Vec<f64>,
    /// The encoders' bits per turn.
    pub encoder_bits: u32,
}

/// The UR5 as its URDF describes it, with every joint column.
fn ur5() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/ur5.yaml");
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// The real UR5: a 4 kg tool 0.1 m beyond the flange (its payload limit is 5 kg), and joint
/// terms of a harmonic-drive arm.
pub fn ur5_with_tool() -> Case {
    let values = joint_values(
        &[0.3, 0.3, 0.2, 0.05, 0.05, 0.05],
        &[2.0, 2.0, 1.0, 0.3, 0.3, 0.3],
        &[3.0, 3.0, 2.0, 0.6, 0.6, 0.6],
        &[0.2, -0.3, 0.1, 0.05, -0.05, 0.02],
    );
    let tool = with_payload(&ur5(), 4.0, Vector3::new(0.0, 0.02, 0.1), 0.05);
    let truth = with_joint_terms(&tool, &values, Some(COULOMB_SMOOTHING));
    let description = with_joint_terms(&ur5(), &[JointTermValues::default(); 6], Some(COULOMB_SMOOTHING));
    case(truth, description, 12)
}

/// The real arm7 (a 1.5 kg payload, its joint terms), described with the armature of a
/// datasheet.
pub fn arm7_case() -> Case {
    let datasheet: Vec<JointTermValues> = arm7_joint_values()
        .iter()
        .map(|v| JointTermValues {
            armature: 0.8 * v.armature,
            ..JointTermValues::default()
        })
        .collect();
    let payload = with_payload(&arm7(), 1.5, Vector3::new(0.0, 0.0, 0.05), 0.04);
    let truth = with_joint_terms(&payload, &arm7_joint_values(), Some(COULOMB_SMOOTHING));
    case(
        truth,
        with_joint_terms(&arm7(), &datasheet, Some(COULOMB_SMOOTHING)),
        14,
    )
}

fn case(truth: Model, description: Model, encoder_bits: u32) -> Case {
    let n = truth.dof();
    let limits = TrajectoryLimits::from_model(&truth, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut trajectory = FourierTrajectory::random(n, 5, 0.1, 1);
    trajectory.fit_into(&limits);
    let mass = NumericDynamics::new(&truth).mass_matrix(&trajectory.at(0.0).q);
    let inertia: Vec<f64> = (0..n).map(|j| mass[(j, j)]).collect();
    let law = ControlLaw::critically_damped(&inertia, 2.0 * PI * BANDWIDTH_HZ);
    let torque_noise = truth
        .joints()
        .iter()
        .map(|j| 0.005 * j.limits.map_or(1.0, |l| l.effort))
        .collect();
    Case {
        truth,
        description,
        law,
        trajectory,
        torque_noise,
        encoder_bits,
    }
}

impl Case {
    /// The log of [`RATE`] Hz over [`SECONDS`] s, read as `logging` says, and the reference at
    /// its times.
    pub fn measure(&self, logging: Logging) -> (Samples, Reference) {
        measure_closed_loop(&self.truth, &self.law, &self.trajectory, SECONDS, RATE, &logging)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    /// How the log reads the robot: the case's encoders, the torque noise, no delay, unit
    /// gains.
    pub fn logging(&self, seed: u64) -> Logging {
        Logging {
            encoder_bits: Some(self.encoder_bits),
            torque_noise: self.torque_noise.clone(),
            torque_delay: 0.0,
            torque_gain: Vec::new(),
            seed,
        }
    }

    /// The robot's loop, with the reference of a log.
    pub fn closed_loop(&self, reference: &Reference) -> ClosedLoop {
        ClosedLoop {
            law: self.law.clone(),
            reference: reference.clone(),
        }
    }

    /// The true base parameters, in the description's base.
    pub fn true_base(&self) -> Vec<f64> {
        BaseParameterSet::compute(&self.description).base_parameters(&self.truth.parameters())
    }

    /// The RMS over the base parameters of an estimate's errors, each in units of its own σ:
    /// about 1 for an estimate whose errors are its noise, well above for a biased one.
    pub fn errors_in_sigma(&self, estimate: &BaseEstimate) -> f64 {
        let truth = self.true_base();
        let squares: f64 = (0..truth.len())
            .map(|k| ((estimate.theta_b[k] - truth[k]) / estimate.std_dev[k]).powi(2))
            .sum();
        (squares / truth.len() as f64).sqrt()
    }

    /// The error norm of an estimate `theta_b`: the RMS torque prediction error on fresh,
    /// noise-free validation data (another random excitation within the limits, 10 s at
    /// 50 Hz, exact q, q̇, q̈), per joint relative to that joint's RMS torque, then the RMS
    /// over the joints (a wrist counts as much as a shoulder). It weighs each base parameter's
    /// error by how much the robot's motion excites it.
    pub fn validation_error(&self, theta_b: &[f64]) -> f64 {
        let base = BaseModel::new(&self.description);
        let truth = DVector::from_vec(self.true_base());
        let estimate = DVector::from_column_slice(theta_b);
        let n = self.truth.dof();
        let limits = TrajectoryLimits::from_model(&self.truth, DEFAULT_ACCELERATION_PER_VELOCITY);
        let mut validation = FourierTrajectory::random(n, 5, 0.1, 99);
        validation.fit_into(&limits);
        let (mut error, mut torque) = (vec![0.0; n], vec![0.0; n]);
        for k in 0..500 {
            let s = validation.at(k as f64 / 50.0);
            let y = base.base_regressor(&s.q, &s.qd, &s.qdd);
            let (predicted, exact) = (&y * &estimate, &y * &truth);
            for j in 0..n {
                error[j] += (predicted[j] - exact[j]).powi(2);
                torque[j] += exact[j].powi(2);
            }
        }
        ((0..n).map(|j| error[j] / torque[j]).sum::<f64>() / n as f64).sqrt()
    }
}
