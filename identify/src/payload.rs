//! A payload (a tool, a grasped object) identified on a robot whose own parameters are known:
//! the ten parameters of one rigid body attached at a frame, with everything else held at the
//! description's values, from joint torques, from a wrist force/torque sensor, or both.
//!
//! - **Torques**: `τ − Y θ_held = Y_body T φ`, the columns of the body that carries the frame
//!   (`T` carries the payload's parameters `φ`, in the frame, to that body's frame), optionally
//!   with the joint terms re-fitted beside it (`τ − Y_rigid θ_held = [Y_body T, Y_joint] [φ; θ_joint]`).
//! - **Force/torque sensor**: the wrench the payload applies to the sensor, in the sensor's
//!   frame, is `w = −B(ω, ω̇, a − g) φ + w₀`: `B` the body regressor of the frame (below), from
//!   the frame's velocity and classical acceleration and gravity, and `w₀` the sensor's offset,
//!   six more unknowns (every sensor has one, and it drifts).
//! - **Both**: the rows of both, each channel weighted by its own noise.
//!
//! The rows go through the identification's weighted least squares (each joint and each
//! sensor axis its own noise, re-estimated from its residuals), so the uncertainty of every
//! number comes with it; then the payload is made physically consistent (its pseudo-inertia
//! positive definite with the identification's margin) by the log-Cholesky map, minimising
//! the whitened misfit `(φ − φ̂)ᵀ Σ⁻¹ (φ − φ̂)` over the payload's marginal information, and
//! a re-fitted joint term that comes out negative (viscous or Coulomb friction, armature) is
//! held at zero and the rest re-solved.
//!
//! The body regressor, with `h = m c`, `I` about the frame origin and `ã = a − g`:
//!
//! ```text
//! f = m ã + (ω̇× + ω×ω×) h
//! n = I ω̇ + ω × I ω − ã × h
//! ```

use crate::data::Samples;
use crate::describe::inertia_of;
use crate::error::IdentifyError;
use crate::least_squares::{estimate, BaseEstimate, Observations};
use crate::levenberg_marquardt::minimise;
use crate::loadable::loadable;
use crate::log_cholesky::{parameters_of, pseudo_inertia, relative_margin, BodyMap, MARGIN};
use crate::observation::motion;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{Frame, JointTermValues, Model, Pose};
use dyngen_runtime::{ReferenceFrame, BODY_PARAMETER_NAMES, PARAMETERS_PER_BODY};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, SMatrix, Vector3};

/// What a payload is identified from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PayloadData {
    /// Joint torques.
    Torques,
    /// A force/torque sensor's wrench (the data's `fx … mz[<frame>]` columns).
    Wrench,
    /// Both, each channel weighted by its noise.
    Both,
}

/// Options of [`identify_payload`].
#[derive(Clone, Debug, PartialEq)]
pub struct PayloadOptions {
    /// The frame the payload is attached at and reported in: by default the sensor's frame
    /// when the data has a wrench, else the end-effector.
    pub frame: Option<String>,
    /// What to identify from: by default everything the data has.
    pub data: Option<PayloadData>,
    /// Re-fit the description's joint terms (friction, armature, offset) from the torques
    /// beside the payload: a load changes the friction of the joints that carry it.
    pub refit_joint_terms: bool,
    /// Cutoff (Hz) of the low-pass filter used when velocities or accelerations are missing.
    pub cutoff: f64,
}

impl Default for PayloadOptions {
    fn default() -> Self {
        PayloadOptions {
            frame: None,
            data: None,
            refit_joint_terms: false,
            cutoff: crate::differentiate::DEFAULT_CUTOFF_HZ,
        }
    }
}

/// An identified payload.
#[derive(Clone, Debug)]
pub struct PayloadEstimate {
    /// The frame the payload is given in.
    pub frame: String,
    pub data: PayloadData,
    pub mass: f64,
    /// Centre of mass in the frame.
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, in the frame's axes.
    pub inertia_com: Matrix3<f64>,
    /// The least squares, before the payload is made physically consistent: every unknown
    /// (the payload's ten parameters in the frame, then re-fitted joint terms, then the
    /// sensor offset), with standard deviations and the noise of each channel (joints, then
    /// the sensor's axes).
    pub least_squares: BaseEstimate,
    /// Whether the least-squares payload was not a physical body, and the consistent one is
    /// the nearest that is (in the whitened misfit).
    pub made_consistent: bool,
    /// The sensor's offset `[f; m]`, when a wrench was used.
    pub sensor_offset: Option<[f64; 6]>,
    /// The re-fitted joint terms, when asked for.
    pub joint_terms: Option<Vec<JointTermValues>>,
    /// The description with the payload welded to the body that carries the frame (and the
    /// re-fitted joint terms): its YAML ([`PayloadEstimate::yaml`]) loads.
    pub model: Model,
    pub samples_used: usize,
    pub differentiated: bool,
    /// With a force/torque sensor: whether its readings fit a payload, and, with torques too,
    /// whether the two sources agree ([`SourceCheck::disagreement`]).
    pub sources: Option<SourceCheck>,
    /// How the estimate was made where it differs from what was asked: joint terms held that
    /// were to be re-fitted.
    pub notes: Vec<String>,
    /// What a user should know about the data and the estimate. (The loader's warnings about
    /// the description with the payload come with the text as written:
    /// [`PayloadEstimate::written`].)
    pub warnings: Vec<String>,
}

impl PayloadEstimate {
    /// The ten standard parameters `[m, m·c, I_O]` of the payload about the frame's origin.
    pub fn parameters(&self) -> [f64; PARAMETERS_PER_BODY] {
        dyngen_runtime::body_parameters(self.mass, &self.com, &self.inertia_com)
    }

    /// The description with the payload as dyngen YAML written to `path`, with the loader's
    /// warnings about that text, each naming `path` and its line there (not in the text: the
    /// loader says them each time the file is loaded).
    pub fn written(
        &self,
        source: &str,
        path: &std::path::Path,
    ) -> Result<(String, Vec<String>), IdentifyError> {
        let text = self.yaml(source);
        let warnings = crate::loadable::warnings_of(&text, path)?;
        Ok((text, warnings))
    }

    /// The description with the payload, as dyngen YAML.
    pub fn yaml(&self, source: &str) -> String {
        crate::describe::to_yaml(&self.model, &self.comment(source))
    }

    /// The description with the payload as a URDF to be written at `urdf_path`, with the
    /// dyngen YAML wrapper that loads it as the robot with the payload when URDF cannot say
    /// everything (see [`to_urdf`](crate::to_urdf)); both with [`PayloadEstimate::yaml`]'s
    /// comment.
    pub fn urdf(&self, source: &str, urdf_path: &std::path::Path) -> Result<crate::UrdfFiles, IdentifyError> {
        crate::urdf::to_urdf(&self.model, &self.comment(source), urdf_path)
    }

    /// The header comment of the written description's files.
    fn comment(&self, source: &str) -> Vec<String> {
        let mut comment = vec![
            format!(
                "The description with a payload identified by `dyngen payload` from {source} ({} samples, {}):",
                self.samples_used,
                match self.data {
                    PayloadData::Torques => "joint torques",
                    PayloadData::Wrench => "force/torque sensor",
                    PayloadData::Both => "joint torques and force/torque sensor",
                }
            ),
            format!(
                "mass {} kg, centre of mass {:?} m in frame '{}', inertia about it (xx, xy, yy, xz, yz, zz) {:?} kg·m²,",
                self.mass,
                self.com.as_slice(),
                self.frame,
                [
                    self.inertia_com[(0, 0)],
                    self.inertia_com[(0, 1)],
                    self.inertia_com[(1, 1)],
                    self.inertia_com[(0, 2)],
                    self.inertia_com[(1, 2)],
                    self.inertia_com[(2, 2)]
                ]
            ),
            "welded to the link that carries the frame.".into(),
        ];
        if self.joint_terms.is_some() {
            comment.push("Joint terms: re-fitted with the payload.".into());
        }
        comment.extend(self.notes.iter().map(|n| format!("note: {n}")));
        comment.extend(self.warnings.iter().map(|w| format!("warning: {w}")));
        comment
    }
}

/// A sensor whose residuals, fitted alone, are more than this many times the noise their
/// sample-to-sample scatter shows fits no payload: its readings are not the wrench of a rigid
/// body in the frame the columns name (a sensor mounted rotated, another frame).
pub const SENSOR_MISFIT_LIMIT: f64 = 20.0;
/// Sources whose fit together leaves some channel more than this many times the noise it has
/// fitted alone disagree: no one payload explains both (a flipped or mis-framed sensor).
pub const DISAGREEMENT_LIMIT: f64 = 10.0;
/// Channels whose noise, fitted together, is below this fraction of their RMS are not
/// compared (noise-free data leaves residuals at rounding, whose ratios mean nothing).
const RESOLVED_NOISE: f64 = 1e-6;

/// How a force/torque sensor's readings and the joint torques agree with a payload and with
/// each other: each source fitted alone, and what fitting them together costs. The checks and
/// their limits: [`SENSOR_MISFIT_LIMIT`], [`DISAGREEMENT_LIMIT`].
#[derive(Clone, Debug, PartialEq)]
pub struct SourceCheck {
    /// The payload's mass from the joint torques alone (`None`: no torques, or the torques
    /// alone do not determine the payload).
    pub mass_from_torques: Option<f64>,
    /// The payload's mass from the sensor alone, and the offset force `[fx, fy, fz]` it then
    /// needs (N).
    pub mass_from_wrench: Option<f64>,
    pub offset_force: Option<Vector3<f64>>,
    /// Per sensor axis (`fx … mz`): the residual σ of the sensor fitted alone over the noise
    /// its sample-to-sample scatter shows (second differences of the residuals): about 1 for
    /// readings a payload explains.
    pub sensor_misfit: Option<[f64; 6]>,
    /// With both sources: per channel (joints, then sensor axes), its noise fitted together
    /// over its noise fitted alone: about 1 for sources that agree.
    pub joint_cost: Vec<f64>,
    /// Why the data cannot be trusted, in one line with the likely cause; `None` when every
    /// check passes.
    pub disagreement: Option<String>,
}

/// The σ of each of `channels` channels of a residual (rows sample-major) from its
/// sample-to-sample scatter: `Σ (r_{k+1} − 2 r_k + r_{k−1})² / 6(N − 2)`, the noise of white
/// noise, blind to anything smooth (a model's misfit).
fn scatter_noise(r: &DVector<f64>, channels: usize) -> Vec<f64> {
    let samples = r.len() / channels;
    (0..channels)
        .map(|c| {
            let at = |k: usize| r[k * channels + c];
            let sum: f64 = (1..samples.saturating_sub(1))
                .map(|k| (at(k + 1) - 2.0 * at(k) + at(k - 1)).powi(2))
                .sum();
            (sum / (6.0 * samples.saturating_sub(2).max(1) as f64)).sqrt()
        })
        .collect()
}

/// The least squares of `y ≈ w x` over `rows` of every sample (of `channels` rows each) and
/// `columns`, with its residual; `None` when those rows do not determine those columns.
fn fit_alone(
    w: &DMatrix<f64>,
    y: &DVector<f64>,
    channels: usize,
    rows: std::ops::Range<usize>,
    columns: &[usize],
    names: &[String],
) -> Option<(BaseEstimate, DVector<f64>)> {
    let samples = y.len() / channels;
    let picked: Vec<usize> = (0..samples)
        .flat_map(|k| rows.clone().map(move |c| k * channels + c))
        .collect();
    let sub = w.select_rows(picked.iter()).select_columns(columns.iter());
    let sub_y = DVector::from_iterator(picked.len(), picked.iter().map(|&r| y[r]));
    let sub_names: Vec<String> = columns.iter().map(|&c| names[c].clone()).collect();
    let observations = Observations::Stacked {
        w: &sub,
        tau: &sub_y,
        n: rows.len(),
    };
    let fit = estimate(observations, &sub_names).ok()?;
    let residual = &sub_y - &sub * DVector::from_column_slice(&fit.theta_b);
    Some((fit, residual))
}

/// The checks of [`SourceCheck`] on the rows `w`, `y` (per sample: `n` torque rows when
/// `torques`, then six sensor rows) and the fit `together` of the columns `free` (the payload,
/// the re-fitted joint terms, the sensor offset at `offset_at`).
#[allow(clippy::too_many_arguments)]
fn check_sources(
    w: &DMatrix<f64>,
    y: &DVector<f64>,
    n: usize,
    torques: bool,
    offset_at: usize,
    names: &[String],
    together: &BaseEstimate,
    sensor_frame: &str,
    gravity: f64,
) -> SourceCheck {
    let first_sensor = if torques { n } else { 0 };
    let channels = first_sensor + 6;
    let payload: Vec<usize> = (0..PARAMETERS_PER_BODY).collect();
    let sensor_columns: Vec<usize> = payload.iter().copied().chain(offset_at..offset_at + 6).collect();
    let torque_columns: Vec<usize> = (0..offset_at).collect();
    let sensor = fit_alone(w, y, channels, first_sensor..channels, &sensor_columns, names);
    let torque = torques
        .then(|| fit_alone(w, y, channels, 0..n, &torque_columns, names))
        .flatten();
    let mass_from_torques = torque.as_ref().map(|(fit, _)| fit.theta_b[0]);
    let mass_from_wrench = sensor.as_ref().map(|(fit, _)| fit.theta_b[0]);
    let offset_force = sensor.as_ref().map(|(fit, _)| {
        let at = PARAMETERS_PER_BODY;
        Vector3::new(fit.theta_b[at], fit.theta_b[at + 1], fit.theta_b[at + 2])
    });
    let sensor_misfit = sensor.as_ref().map(|(fit, residual)| {
        let scatter = scatter_noise(residual, 6);
        std::array::from_fn(|c| fit.joint_noise[c] / scatter[c].max(f64::MIN_POSITIVE))
    });
    // Channels fitted together against each alone.
    let mut joint_cost = Vec::new();
    if torques {
        let rms: Vec<f64> = (0..channels)
            .map(|c| {
                let samples = y.len() / channels;
                ((0..samples).map(|k| y[k * channels + c].powi(2)).sum::<f64>() / samples as f64).sqrt()
            })
            .collect();
        let alone: Vec<Option<f64>> = (0..channels)
            .map(|c| match c < n {
                true => torque.as_ref().map(|(fit, _)| fit.joint_noise[c]),
                false => sensor.as_ref().map(|(fit, _)| fit.joint_noise[c - n]),
            })
            .collect();
        joint_cost = (0..channels)
            .map(|c| match alone[c] {
                Some(a) if together.joint_noise[c] > RESOLVED_NOISE * rms[c] => {
                    together.joint_noise[c] / a.max(f64::MIN_POSITIVE)
                }
                _ => 1.0,
            })
            .collect();
    }
    let axis = |c: usize| OFFSET_NAMES[c];
    let worst = |values: &[f64]| {
        (0..values.len())
            .max_by(|&a, &b| values[a].total_cmp(&values[b]))
            .map(|c| (c, values[c]))
    };
    let channel_name = |c: usize| match c < first_sensor {
        true => format!("joint {}", c + 1),
        false => axis(c - first_sensor).to_string(),
    };
    // The likely cause, from the sources alone.
    let weight = mass_from_torques.or(mass_from_wrench).map(|m| m.abs() * gravity);
    let offset_the_weight = match (offset_force, weight) {
        (Some(f), Some(weight)) if f.norm() > 0.5 * weight => Some(format!(
            "; the offset force it needs, {:.1} N, is the size of the payload's weight, {weight:.1} N",
            f.norm()
        )),
        _ => None,
    };
    let misfit = sensor_misfit
        .and_then(|m: [f64; 6]| worst(&m))
        .filter(|&(_, r)| r > SENSOR_MISFIT_LIMIT);
    let disagree = worst(&joint_cost).filter(|&(_, r)| r > DISAGREEMENT_LIMIT);
    let flipped = matches!((mass_from_torques, mass_from_wrench), (Some(t), Some(s)) if t > 0.0 && s < 0.0);
    let disagreement = if let Some((c, r)) = disagree {
        let cause = if flipped {
            format!(
                "the sensor's sign: from the sensor alone the payload weighs {:.3} kg, from the torques {:.3} kg; \
                 its columns look like the wrench the sensor applies to the load, the opposite of the \
                 convention (the wrench the load applies to the sensor): negate its six columns",
                mass_from_wrench.unwrap_or_default(),
                mass_from_torques.unwrap_or_default()
            )
        } else if misfit.is_some() || offset_the_weight.is_some() {
            format!(
                "the sensor's frame: its readings are not a wrench in the axes of '{sensor_frame}' (a sensor \
                 mounted rotated, or another frame){}",
                offset_the_weight.clone().unwrap_or_default()
            )
        } else {
            format!(
                "the payload weighs {:.3} kg from the sensor alone and {:.3} kg from the torques; check the \
                 sensor's frame and units, and that the description is the robot's",
                mass_from_wrench.unwrap_or(f64::NAN),
                mass_from_torques.unwrap_or(f64::NAN)
            )
        };
        Some(format!(
            "the force/torque sensor and the joint torques disagree: fitted together, {} has {r:.0} times \
             the noise it has alone; likely cause: {cause}",
            channel_name(c)
        ))
    } else {
        misfit.map(|(c, r)| {
            format!(
                "the force/torque sensor's readings fit no payload: its residuals are {r:.0} times the noise \
                 their scatter shows ({}); likely cause: the sensor's frame: its readings are not a wrench in \
                 the axes of '{sensor_frame}' (a sensor mounted rotated, or another frame){}",
                axis(c),
                offset_the_weight.unwrap_or_default()
            )
        })
    };
    SourceCheck {
        mass_from_torques,
        mass_from_wrench,
        offset_force,
        sensor_misfit,
        joint_cost,
        disagreement,
    }
}

/// `p`'s ten parameters (about the origin of the frame they are given in) seen from another
/// frame, `pose` being the first frame in the second. The pseudo-inertia `∫ [r; 1][r; 1]ᵀ dm`
/// moves by congruence with the homogeneous transform, `J' = T J Tᵀ`.
pub(crate) fn parameters_in(p: &[f64; PARAMETERS_PER_BODY], pose: &Pose) -> [f64; PARAMETERS_PER_BODY] {
    let mut t = Matrix4::identity();
    t.fixed_view_mut::<3, 3>(0, 0).copy_from(&pose.rotation);
    t.fixed_view_mut::<3, 1>(0, 3).copy_from(&pose.translation);
    parameters_of(&(t * pseudo_inertia(p) * t.transpose()))
}

/// The linear map of [`parameters_in`] as a matrix.
fn parameters_in_matrix(pose: &Pose) -> SMatrix<f64, 10, 10> {
    let mut t = SMatrix::<f64, 10, 10>::zeros();
    for k in 0..PARAMETERS_PER_BODY {
        let mut e = [0.0; PARAMETERS_PER_BODY];
        e[k] = 1.0;
        t.set_column(k, &SMatrix::<f64, 10, 1>::from(parameters_in(&e, pose)));
    }
    t
}

/// `B` with `[f; n] = B φ`: the wrench that moves a body of parameters `φ` (about the frame
/// origin, in its axes) at angular velocity `w`, angular acceleration `dw` and origin
/// acceleration minus gravity `a`, all in the frame.
pub(crate) fn body_regressor(w: &Vector3<f64>, dw: &Vector3<f64>, a: &Vector3<f64>) -> SMatrix<f64, 6, 10> {
    let mut b = SMatrix::<f64, 6, 10>::zeros();
    let wx = w.cross_matrix();
    b.fixed_view_mut::<3, 1>(0, 0).copy_from(a);
    b.fixed_view_mut::<3, 3>(0, 1)
        .copy_from(&(dw.cross_matrix() + wx * wx));
    b.fixed_view_mut::<3, 3>(3, 1).copy_from(&(-a.cross_matrix()));
    // `I v` as a matrix of the six inertia entries [xx, xy, yy, xz, yz, zz].
    let of = |v: &Vector3<f64>| {
        SMatrix::<f64, 3, 6>::from_row_slice(&[
            v.x, v.y, 0.0, v.z, 0.0, 0.0, //
            0.0, v.x, v.y, 0.0, v.z, 0.0, //
            0.0, 0.0, 0.0, v.x, v.y, v.z,
        ])
    };
    b.fixed_view_mut::<3, 6>(3, 4).copy_from(&(of(dw) + wx * of(w)));
    b
}

/// The pose of frame `b` in frame `a`, both on one body.
fn relative(a: &Frame, b: &Frame) -> Pose {
    let rt = a.placement.rotation.transpose();
    Pose {
        rotation: rt * b.placement.rotation,
        translation: rt * (b.placement.translation - a.placement.translation),
    }
}

fn find_frame<'m>(model: &'m Model, name: &str, what: &str) -> Result<&'m Frame, IdentifyError> {
    model.frames().iter().find(|f| f.name == name).ok_or_else(|| {
        let names: Vec<&str> = model.frames().iter().map(|f| f.name.as_str()).collect();
        IdentifyError::data(format!(
            "{what} '{name}' is not a frame of the description (its frames: {}; name others with `frames:`)",
            names.join(", ")
        ))
    })
}

const OFFSET_NAMES: [&str; 6] = ["fx", "fy", "fz", "mx", "my", "mz"];

/// Identifies a payload attached at a frame of `model`, with `model`'s own parameters held;
/// see the module docs.
pub fn identify_payload(
    model: &Model,
    samples: &Samples,
    options: &PayloadOptions,
) -> Result<PayloadEstimate, IdentifyError> {
    crate::pipeline::refuse_floating_base(model)?;
    let data = match (options.data, samples.tau.is_some(), samples.wrench.is_some()) {
        (Some(data), _, _) => data,
        (None, true, true) => PayloadData::Both,
        (None, true, false) => PayloadData::Torques,
        (None, false, true) => PayloadData::Wrench,
        (None, false, false) => {
            return Err(samples.locate(IdentifyError::data(
                "the data has neither torque columns (tau[<joint>]) nor a force/torque sensor's (fx … mz[<frame>])",
            )))
        }
    };
    let torques = matches!(data, PayloadData::Torques | PayloadData::Both);
    let wrench = matches!(data, PayloadData::Wrench | PayloadData::Both);
    let tau = match (torques, &samples.tau) {
        (true, None) => {
            return Err(samples.locate(IdentifyError::data(
                "identifying from torques, but the data has no torque columns (tau[<joint>])",
            )))
        }
        (_, tau) => tau.as_ref().filter(|_| torques),
    };
    let sensor = match (wrench, &samples.wrench, &samples.sensor_frame) {
        (true, Some(w), Some(frame)) => Some((w, find_frame(model, frame, "the sensor frame")?)),
        (true, _, _) => return Err(samples.locate(IdentifyError::data(
            "identifying from a force/torque sensor, but the data has no wrench columns (fx … mz[<frame>])",
        ))),
        (false, _, _) => None,
    };
    let frame_name = options
        .frame
        .clone()
        .or_else(|| sensor.map(|(_, f)| f.name.clone()))
        .unwrap_or_else(|| model.end_effector().name.clone());
    let frame = find_frame(model, &frame_name, "the payload frame")?;
    if let Some((_, s)) = sensor {
        if s.parent != frame.parent {
            return Err(IdentifyError::data(format!(
                "the payload frame '{}' and the sensor frame '{}' are on different links: the sensor \
                 measures only what is beyond it",
                frame.name, s.name
            )));
        }
    }
    let refit = torques && options.refit_joint_terms && !model.joint_terms().kinds.is_empty();
    let (mut warnings, mut notes) = (Vec::new(), Vec::new());
    if options.refit_joint_terms && !refit {
        notes.push(if torques {
            "the description chooses no joint terms: there are none to re-fit".to_string()
        } else {
            "joint terms are re-fitted from torques only: held".to_string()
        });
    }
    samples.check(model).map_err(|e| samples.locate(e))?;
    let motion = motion(samples, options.cutoff).map_err(|e| samples.locate(e))?;
    let n = model.dof();
    let inertial = model.inertial_parameter_count();
    let joint_count = model.parameter_count() - inertial;
    let refit_count = if refit { joint_count } else { 0 };
    let offset_at = PARAMETERS_PER_BODY + refit_count;
    let columns = offset_at + if wrench { 6 } else { 0 };
    let channels = (if torques { n } else { 0 }) + (if wrench { 6 } else { 0 });
    let theta: Vec<f64> = model.parameters();
    let to_body = parameters_in_matrix(&frame.placement);
    let to_sensor = sensor.map(|(_, s)| parameters_in_matrix(&relative(s, frame)));
    let body = PARAMETERS_PER_BODY * crate::pipeline::carrier(frame);
    let dynamics = NumericDynamics::new(model);
    let rows = motion.kept.len() * channels;
    let mut w = DMatrix::zeros(rows, columns);
    let mut y = DVector::zeros(rows);
    for (i, &k) in motion.kept.iter().enumerate() {
        let (q, qd, qdd) = (&samples.q[k], &motion.qd[i], &motion.qdd[i]);
        let row = i * channels;
        if let Some(tau) = tau {
            let full = dynamics.regressor(q, qd, qd, qdd);
            let payload = full.columns(body, PARAMETERS_PER_BODY) * to_body;
            w.view_mut((row, 0), (n, PARAMETERS_PER_BODY)).copy_from(&payload);
            let held_columns = if refit { inertial } else { theta.len() };
            let held = full.columns(0, held_columns) * DVector::from_column_slice(&theta[..held_columns]);
            if refit {
                w.view_mut((row, PARAMETERS_PER_BODY), (n, joint_count))
                    .copy_from(&full.columns(inertial, joint_count));
            }
            for j in 0..n {
                y[row + j] = tau[k][j] - held[j];
            }
        }
        if let (Some((measured, s)), Some(to_sensor)) = (sensor, &to_sensor) {
            let row = row + if torques { n } else { 0 };
            let values = dynamics
                .frame_motion(&s.name, q, qd)
                .expect("the sensor frame is the model's");
            let (rotation, _) = values.pose();
            let velocity = values.velocity(ReferenceFrame::Local);
            let acceleration = values.classical_acceleration(ReferenceFrame::Local, qdd);
            let (wv, dw) = (
                Vector3::new(velocity[3], velocity[4], velocity[5]),
                Vector3::new(acceleration[3], acceleration[4], acceleration[5]),
            );
            let a = Vector3::new(acceleration[0], acceleration[1], acceleration[2])
                - rotation.transpose() * model.gravity();
            let b = -body_regressor(&wv, &dw, &a) * to_sensor;
            w.view_mut((row, 0), (6, PARAMETERS_PER_BODY)).copy_from(&b);
            w.view_mut((row, offset_at), (6, 6))
                .copy_from(&DMatrix::<f64>::identity(6, 6));
            for c in 0..6 {
                y[row + c] = measured[k][c];
            }
        }
    }
    let mut names: Vec<String> = BODY_PARAMETER_NAMES
        .iter()
        .map(|p| format!("payload {p}"))
        .collect();
    if refit {
        names.extend(model.parameter_names()[inertial..].iter().cloned());
    }
    if wrench {
        names.extend(OFFSET_NAMES.iter().map(|c| format!("sensor offset {c}")));
    }
    // Re-fitted joint terms that must not be negative and come out so are held at zero, one
    // at a time, the most negative first (an active set, as in non-negative least squares).
    let term_kinds = &model.joint_terms().kinds;
    let non_negative = |c: usize| {
        (PARAMETERS_PER_BODY..offset_at).contains(&c)
            && term_kinds[(c - PARAMETERS_PER_BODY) % term_kinds.len()].is_non_negative()
    };
    let mut held_at_zero: Vec<usize> = Vec::new();
    let least_squares = loop {
        let free: Vec<usize> = (0..columns).filter(|c| !held_at_zero.contains(c)).collect();
        let sub = w.select_columns(free.iter());
        let sub_names: Vec<String> = free.iter().map(|&c| names[c].clone()).collect();
        let observations = Observations::Stacked {
            w: &sub,
            tau: &y,
            n: channels,
        };
        let fit = estimate(observations, &sub_names)?;
        let negative = free
            .iter()
            .enumerate()
            .filter(|&(_, &c)| non_negative(c))
            .map(|(i, &c)| (fit.theta_b[i], c))
            .filter(|(v, _)| *v < 0.0)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match negative {
            Some((_, c)) => held_at_zero.push(c),
            None => break (fit, free),
        }
    };
    let (fit, free) = least_squares;
    let mut x = vec![0.0; columns];
    for (i, &c) in free.iter().enumerate() {
        x[c] = fit.theta_b[i];
    }
    let sources = sensor.map(|(_, s)| {
        check_sources(
            &w,
            &y,
            n,
            torques,
            offset_at,
            &names,
            &fit,
            &s.name,
            model.gravity().norm(),
        )
    });
    let disagreement = sources.as_ref().and_then(|s| s.disagreement.clone());
    let (payload, made_consistent) = match consistent_payload(&fit, &x[..PARAMETERS_PER_BODY]) {
        Ok(consistent) => consistent,
        Err(e) => {
            return Err(match &disagreement {
                Some(why) => samples.locate(IdentifyError::data(why.clone())),
                None if wrench && !torques && x[0] < 0.0 => IdentifyError::Unidentifiable(format!(
                "{e}; a negative mass from a force/torque sensor alone is the sign of a sensor that reports \
                     the wrench it applies to the load, the opposite of the convention (the wrench the load \
                     applies to the sensor): negate its six columns"
            )),
                None => e,
            })
        }
    };
    warnings.extend(disagreement);
    // The other unknowns given the consistent payload: their least squares conditioned on it.
    let information = information(&fit);
    let others: Vec<usize> = (PARAMETERS_PER_BODY..free.len()).collect();
    if !others.is_empty() {
        let i_oo = information
            .select_rows(others.iter())
            .select_columns(others.iter());
        let i_op = information
            .select_rows(others.iter())
            .columns(0, PARAMETERS_PER_BODY)
            .into_owned();
        let shift = DVector::from_fn(PARAMETERS_PER_BODY, |r, _| payload[r] - x[r]);
        if let Some(chol) = i_oo.cholesky() {
            let correction = chol.solve(&(i_op * shift));
            for (i, &o) in others.iter().enumerate() {
                x[free[o]] -= correction[i];
            }
        }
    }
    x[..PARAMETERS_PER_BODY].copy_from_slice(&payload);
    // The description with the payload welded on and the re-fitted joint terms.
    let mut theta_new = theta.clone();
    let in_body = parameters_in(&payload, &frame.placement);
    for k in 0..PARAMETERS_PER_BODY {
        theta_new[body + k] += in_body[k];
    }
    if refit {
        theta_new[inertial..].copy_from_slice(&x[PARAMETERS_PER_BODY..offset_at]);
    }
    let with_payload = loadable(model, &theta_new)
        .map_err(|why| IdentifyError::InvalidEstimate(format!("the description with the payload: {why}")))?;
    let carried = inertia_of(&payload);
    Ok(PayloadEstimate {
        frame: frame.name.clone(),
        data,
        mass: carried.mass,
        com: carried.com,
        inertia_com: carried.inertia_com,
        least_squares: fit,
        made_consistent,
        sensor_offset: wrench.then(|| std::array::from_fn(|c| x[offset_at + c])),
        joint_terms: refit.then(|| with_payload.joint_terms().values.clone()),
        model: with_payload,
        samples_used: motion.kept.len(),
        differentiated: motion.differentiated,
        sources,
        notes,
        warnings,
    })
}

/// The information matrix `Σ⁻¹` of an estimate, in its own units.
fn information(fit: &BaseEstimate) -> DMatrix<f64> {
    let s = &fit.scale;
    DMatrix::from_fn(s.len(), s.len(), |i, j| {
        fit.information_scaled[(i, j)] / (s[i] * s[j])
    })
}

/// The physically consistent payload nearest the least squares' `p` in the whitened misfit
/// of its marginal information, and whether it moved.
fn consistent_payload(
    fit: &BaseEstimate,
    p: &[f64],
) -> Result<([f64; PARAMETERS_PER_BODY], bool), IdentifyError> {
    if p[0].is_nan() || p[0] <= 0.0 {
        return Err(IdentifyError::Unidentifiable(format!(
            "the data shows no payload: its estimated mass is {:.3e} kg (±{:.1e})",
            p[0], fit.std_dev[0]
        )));
    }
    let p: [f64; PARAMETERS_PER_BODY] = std::array::from_fn(|k| p[k]);
    // The payload's marginal information: the inverse of its block of the covariance.
    let covariance = information(fit)
        .cholesky()
        .map(|c| c.inverse())
        .ok_or_else(|| IdentifyError::Unidentifiable("the payload's information is singular".into()))?;
    let block = covariance
        .view((0, 0), (PARAMETERS_PER_BODY, PARAMETERS_PER_BODY))
        .into_owned();
    let r = block
        .cholesky()
        .map(|c| c.inverse())
        .and_then(|i| ((&i + i.transpose()) * 0.5).cholesky())
        .map(|c| c.l().transpose())
        .ok_or_else(|| IdentifyError::Unidentifiable("the payload's covariance is singular".into()))?;
    let c = Vector3::new(p[1], p[2], p[3]) / p[0];
    let gyration = (0.5 * (p[4] + p[6] + p[9]).max(0.0) / p[0]).sqrt();
    let map = BodyMap {
        length: c.norm().max(gyration).max(0.01),
    };
    let start = map.free_numbers(&p).ok_or_else(|| {
        IdentifyError::Unidentifiable("the estimated payload has no positive inertia to keep".into())
    })?;
    if relative_margin(&p) >= MARGIN {
        return Ok((p, false));
    }
    let target = DVector::from_column_slice(&p);
    let residual = |phi: &[f64]| &r * (DVector::from_column_slice(&map.parameters(phi)) - &target);
    let jacobian = |phi: &[f64]| {
        let j = map.jacobian(phi);
        &r * DMatrix::from_fn(PARAMETERS_PER_BODY, PARAMETERS_PER_BODY, |i, k| j[(i, k)])
    };
    let minimum = minimise(residual, jacobian, start.to_vec(), 1e-6);
    Ok((map.parameters(&minimum.x), true))
}
