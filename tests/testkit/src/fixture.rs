//! Reference values computed by Pinocchio 4.1 (`codegen/tests/fixtures/`, made by
//! `tools/fixtures.py`: see `codegen/tests/fixtures/README.md`), and the model they describe,
//! built from their own joint placements.

use dyngen_codegen::model::{Body, Frame, Inertia, Joint, JointKind, Model, Pose};
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde_json::Value;

pub struct State {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    pub vr: Vec<f64>,
    pub ar: Vec<f64>,
    pub d: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub g: Vec<f64>,
    pub tau: Vec<f64>,
    pub tau_ref: Vec<f64>,
    pub j: DMatrix<f64>,
    pub jdot: DMatrix<f64>,
    pub ee_translation: Vec<f64>,
    pub ee_rotation: DMatrix<f64>,
    pub y: DMatrix<f64>,
    /// Forward dynamics at `(q, v, tau)` (equals `a`).
    pub aba: Vec<f64>,
    pub minv: DMatrix<f64>,
    pub dtau_dq: DMatrix<f64>,
    pub dtau_dv: DMatrix<f64>,
    pub dqdd_dq: DMatrix<f64>,
    pub dqdd_dv: DMatrix<f64>,
}

pub struct Fixture {
    pub json: Value,
    pub joint_names: Vec<String>,
    pub pi: Vec<f64>,
    pub states: Vec<State>,
}

/// A JSON array of numbers.
pub fn vector(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

pub fn matrix(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v.as_array().expect("rows").iter().map(vector).collect();
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

fn pose(v: &Value) -> Pose {
    let r = matrix(&v["rotation"]);
    Pose {
        rotation: Matrix3::from_fn(|i, j| r[(i, j)]),
        translation: Vector3::from_vec(vector(&v["translation"])),
    }
}

pub fn load(robot: &str) -> Fixture {
    let path = format!(
        "{}/../../codegen/tests/fixtures/{robot}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("fixture file")).expect("json");
    let states = json["states"]
        .as_array()
        .expect("states")
        .iter()
        .map(|s| State {
            q: vector(&s["q"]),
            v: vector(&s["v"]),
            a: vector(&s["a"]),
            vr: vector(&s["vr"]),
            ar: vector(&s["ar"]),
            d: matrix(&s["D"]),
            c: matrix(&s["C"]),
            g: vector(&s["g"]),
            tau: vector(&s["tau"]),
            tau_ref: vector(&s["tau_ref"]),
            j: matrix(&s["J"]),
            jdot: matrix(&s["Jdot"]),
            ee_translation: vector(&s["ee_translation"]),
            ee_rotation: matrix(&s["ee_rotation"]),
            y: matrix(&s["Y"]),
            aba: vector(&s["aba"]),
            minv: matrix(&s["Minv"]),
            dtau_dq: matrix(&s["dtau_dq"]),
            dtau_dv: matrix(&s["dtau_dv"]),
            dqdd_dq: matrix(&s["dqdd_dq"]),
            dqdd_dv: matrix(&s["dqdd_dv"]),
        })
        .collect();
    let joint_names = json["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_owned())
        .collect();
    let pi = vector(&json["pi"]);
    Fixture {
        json,
        joint_names,
        pi,
        states,
    }
}

impl Fixture {
    /// The model exactly as the fixture states it (placements, axes, bodies), independent of
    /// dyngen's description loaders.
    pub fn model(&self) -> Model {
        let j = &self.json;
        let names = &self.joint_names;
        let joints = j["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|jt| Joint {
                name: jt["name"].as_str().unwrap().to_owned(),
                parent: names.iter().position(|n| n == jt["parent"].as_str().unwrap()),
                kind: match jt["kind"].as_str().unwrap() {
                    "prismatic" => JointKind::Prismatic,
                    _ => JointKind::Revolute,
                },
                origin: pose(&jt["placement"]),
                axis: Vector3::from_vec(vector(&jt["axis"])),
                limits: None,
            })
            .collect();
        let bodies = j["bodies"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| Body {
                name: b["joint"].as_str().unwrap().to_owned(),
                inertia: Inertia {
                    mass: b["mass"].as_f64().unwrap(),
                    com: Vector3::from_vec(vector(&b["com"])),
                    inertia_com: {
                        let m = matrix(&b["inertia_about_com"]);
                        Matrix3::from_fn(|r, c| m[(r, c)])
                    },
                },
            })
            .collect();
        let ee_parent = names
            .iter()
            .position(|n| n == j["ee_parent_joint"].as_str().unwrap())
            .unwrap();
        Model::new(
            j["robot"].as_str().unwrap(),
            joints,
            bodies,
            Vector3::from_vec(vector(&j["gravity"])),
            Frame {
                name: j["ee_frame"].as_str().unwrap().to_owned(),
                parent: Some(ee_parent),
                placement: pose(&j["ee_placement_in_parent_joint"]),
            },
        )
        .expect("the fixture's model is valid")
    }
}

impl Fixture {
    /// The reference values in another joint order (`names`, e.g. dyngen's), by joint name:
    /// Pinocchio and dyngen both number a tree depth-first but may visit children in another
    /// order (example-robot-data's Alex upper body: Pinocchio numbers the left arm before the
    /// neck, dyngen after it). Vectors, the rows and columns of joint-by-joint matrices, the
    /// columns of `J` and `J̇`, the rows of `Y` and the ten-parameter blocks of `pi` and `Y`
    /// move with their joint. `json` (and so `model()`) keeps Pinocchio's order.
    pub fn reordered(&self, names: &[&str]) -> Fixture {
        let n = self.joint_names.len();
        assert_eq!(names.len(), n, "number of joints");
        let of: Vec<usize> = names
            .iter()
            .map(|name| {
                self.joint_names
                    .iter()
                    .position(|m| m == name)
                    .unwrap_or_else(|| panic!("joint '{name}' is not in the fixture"))
            })
            .collect();
        const BODY: usize = dyngen_runtime::PARAMETERS_PER_BODY;
        let vector = |v: &[f64]| of.iter().map(|&k| v[k]).collect::<Vec<f64>>();
        let square = |m: &DMatrix<f64>| DMatrix::from_fn(n, n, |i, j| m[(of[i], of[j])]);
        let columns = |m: &DMatrix<f64>| DMatrix::from_fn(m.nrows(), n, |i, j| m[(i, of[j])]);
        let block = |j: usize| of[j / BODY] * BODY + j % BODY;
        let states = self
            .states
            .iter()
            .map(|s| State {
                q: vector(&s.q),
                v: vector(&s.v),
                a: vector(&s.a),
                vr: vector(&s.vr),
                ar: vector(&s.ar),
                d: square(&s.d),
                c: square(&s.c),
                g: vector(&s.g),
                tau: vector(&s.tau),
                tau_ref: vector(&s.tau_ref),
                j: columns(&s.j),
                jdot: columns(&s.jdot),
                ee_translation: s.ee_translation.clone(),
                ee_rotation: s.ee_rotation.clone(),
                y: DMatrix::from_fn(n, n * BODY, |i, j| s.y[(of[i], block(j))]),
                aba: vector(&s.aba),
                minv: square(&s.minv),
                dtau_dq: square(&s.dtau_dq),
                dtau_dv: square(&s.dtau_dv),
                dqdd_dq: square(&s.dqdd_dq),
                dqdd_dv: square(&s.dqdd_dv),
            })
            .collect();
        Fixture {
            json: self.json.clone(),
            joint_names: names.iter().map(|s| s.to_string()).collect(),
            pi: (0..n * BODY).map(|j| self.pi[block(j)]).collect(),
            states,
        }
    }
}

/// The generic dynamics against the rigid-body fields of one Pinocchio state: end-effector pose,
/// `J`, `J̇`, `D`, `C`, `g`, `τ` and the Slotine–Li torque, each to `tol` relative. `at` names
/// a field in a failure message.
pub fn assert_rigid_body_fields(
    dynamics: &dyngen_codegen::dynamics::NumericDynamics,
    s: &State,
    at: &dyn Fn(&str) -> String,
    tol: f64,
) {
    use crate::{assert_close, column};
    let (rot, pos) = dynamics.end_effector_pose(&s.q);
    assert_close(
        &at("ee translation"),
        &column(pos.as_slice()),
        &column(&s.ee_translation),
        tol,
    );
    assert_close(
        &at("ee rotation"),
        &DMatrix::from_column_slice(3, 3, rot.as_slice()),
        &s.ee_rotation,
        tol,
    );
    assert_close(&at("J"), &dynamics.jacobian(&s.q), &s.j, tol);
    assert_close(&at("J̇"), &dynamics.jacobian_dot(&s.q, &s.v), &s.jdot, tol);
    assert_close(&at("D"), &dynamics.mass_matrix(&s.q), &s.d, tol);
    assert_close(&at("C"), &dynamics.coriolis_matrix(&s.q, &s.v), &s.c, tol);
    let g = dynamics.gravity_torque(&s.q);
    assert_close(&at("g"), &column(g.as_slice()), &column(&s.g), tol);
    let tau = dynamics.inverse_dynamics(&s.q, &s.v, &s.a);
    assert_close(&at("τ"), &column(tau.as_slice()), &column(&s.tau), tol);
    let tau_ref = dynamics.slotine_li(&s.q, &s.v, &s.vr, &s.ar, true);
    assert_close(
        &at("Slotine–Li τ"),
        &column(tau_ref.as_slice()),
        &column(&s.tau_ref),
        tol,
    );
}

/// The generic dynamics against the forward-dynamics fields of one Pinocchio state: `q̈`,
/// `D⁻¹`, `(∂τ/∂q, ∂τ/∂q̇)` and `(∂q̈/∂q, ∂q̈/∂q̇)`, each to `tol` relative.
pub fn assert_forward_dynamics_fields(
    dynamics: &dyngen_codegen::dynamics::NumericDynamics,
    s: &State,
    at: &dyn Fn(&str) -> String,
    tol: f64,
) {
    use crate::{assert_close, column};
    let qdd = dynamics.forward_dynamics(&s.q, &s.v, &s.tau);
    assert_close(&at("q̈"), &column(qdd.as_slice()), &column(&s.aba), tol);
    assert_close(&at("D⁻¹"), &dynamics.mass_matrix_inverse(&s.q), &s.minv, tol);
    let (dq, dv) = dynamics.inverse_dynamics_derivatives(&s.q, &s.v, &s.a);
    assert_close(&at("∂τ/∂q"), &dq, &s.dtau_dq, tol);
    assert_close(&at("∂τ/∂q̇"), &dv, &s.dtau_dv, tol);
    let (dq, dv) = dynamics.forward_dynamics_derivatives(&s.q, &s.v, &s.tau);
    assert_close(&at("∂q̈/∂q"), &dq, &s.dqdd_dq, tol);
    assert_close(&at("∂q̈/∂q̇"), &dv, &s.dqdd_dv, tol);
}
