//! Pinocchio 4.1's values for floating-base robots (`codegen/tests/fixtures/floating/` and
//! `constrained/`, made by `tools/floating_fixtures.py` and `tools/constraint_fixtures.py`), and the maps from Pinocchio's joint order to a loaded
//! model's, joint by joint name.

use crate::fixture::{matrix, vector};
use crate::workspace_root;
use dyngen_codegen::model::{Contact, Model};
use dyngen_runtime::{ContactKind, Pose, ProximalSettings, ReferenceFrame, Stabilisation};
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde_json::Value;

/// The fixture of `robot` (`solo12`, `g1`) as JSON.
pub fn load(robot: &str) -> Value {
    load_from("floating", robot)
}

/// The constrained-dynamics fixture of `robot` (`codegen/tests/fixtures/constrained/`, made by
/// `tools/constraint_fixtures.py`), in the same joint order as [`load`]'s.
pub fn load_constrained(robot: &str) -> Value {
    load_from("constrained", robot)
}

/// The contacts a constrained fixture lists under `"contacts"` (`frame`, `kind`, `reference`,
/// and `to` for a loop), resolved on `model`.
pub fn contacts(model: &Model, listing: &Value) -> Vec<Contact> {
    (listing["contacts"].as_array().unwrap().iter())
        .map(|c| {
            let kind = match c["kind"].as_str().unwrap() {
                "point" => ContactKind::Point,
                _ => ContactKind::Frame,
            };
            let reference = match c["reference"].as_str().unwrap() {
                "local" => ReferenceFrame::Local,
                _ => ReferenceFrame::LocalWorldAligned,
            };
            let contact = Contact::at(model, c["frame"].as_str().unwrap(), kind, reference).unwrap();
            match c["to"].as_str() {
                Some(to) => contact.to(model, to).unwrap(),
                None => contact,
            }
        })
        .collect()
}

/// A constrained state's anchors (`"anchors"`: rotation and translation each).
pub fn anchors(state: &Value) -> Vec<Pose> {
    let anchor = |pose: &Value| {
        let r = matrix(&pose["rotation"]);
        Pose {
            rotation: Matrix3::from_fn(|i, j| r[(i, j)]),
            translation: Vector3::from_column_slice(&vector(&pose["translation"])),
        }
    };
    state["anchors"].as_array().unwrap().iter().map(anchor).collect()
}

/// The two solves a constrained fixture holds per state, by their labels: `plain`, and
/// `stabilised` towards `anchors` with the fixture's Baumgarte gains.
pub fn solves<'a>(fixture: &Value, anchors: &'a [Pose]) -> [(&'static str, Option<Stabilisation<'a>>); 2] {
    let gains = &fixture["baumgarte"];
    let stabilised = Stabilisation {
        anchors,
        kp: gains["kp"].as_f64().unwrap(),
        kd: gains["kd"].as_f64().unwrap(),
    };
    [("plain", None), ("stabilised", Some(stabilised))]
}

/// A constrained fixture's proximal settings (`"proximal"`: `mu`, `max_iter`, `accuracy`).
pub fn proximal(fixture: &Value) -> ProximalSettings {
    let p = &fixture["proximal"];
    ProximalSettings {
        mu: p["mu"].as_f64().unwrap(),
        max_iterations: p["max_iter"].as_u64().unwrap() as usize,
        accuracy: p["accuracy"].as_f64().unwrap(),
    }
}

fn load_from(directory: &str, robot: &str) -> Value {
    let path = workspace_root().join(format!("codegen/tests/fixtures/{directory}/{robot}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Index maps between Pinocchio's order and a model's: `velocity[k]` is the model's velocity
/// index of Pinocchio's velocity entry `k` (the base's six first in both), `body[k]` the
/// model's parameter block (0 the base body) of Pinocchio's body `k`. With mimic joints the
/// velocities are the coordinates' (`joint_names`) and the bodies every joint's (`joints`).
pub struct Order {
    pub velocity: Vec<usize>,
    pub body: Vec<usize>,
}

impl Order {
    pub fn new(model: &Model, fixture: &Value) -> Order {
        let name = |j: usize| model.joints()[j].name.as_str();
        let coordinates: Vec<&str> = model.coordinate_joints().into_iter().map(name).collect();
        let joints: Vec<&str> = (0..model.joints().len()).map(name).collect();
        // A joint is its name, or an object with one.
        let names = |field: &str| -> Vec<&str> {
            (fixture[field]
                .as_array()
                .unwrap_or_else(|| panic!("{field}"))
                .iter())
            .map(|n| n.as_str().or(n["name"].as_str()).expect("a joint name"))
            .collect()
        };
        let theirs = names("joint_names");
        let their_bodies = match fixture["joints"].is_array() {
            true => names("joints"),
            false => theirs.clone(),
        };
        let position = |ours: &[&str], name: &str| {
            ours.iter()
                .position(|o| *o == name)
                .unwrap_or_else(|| panic!("joint {name} is not in the model"))
        };
        assert_eq!(coordinates.len(), theirs.len(), "the coordinates");
        assert_eq!(joints.len(), their_bodies.len(), "the moving joints");
        let mut velocity: Vec<usize> = (0..6).collect();
        velocity.extend(theirs.iter().map(|n| 6 + position(&coordinates, n)));
        let mut body = vec![0];
        body.extend(their_bodies.iter().map(|n| 1 + position(&joints, n)));
        Order { velocity, body }
    }

    /// A Pinocchio velocity-indexed vector in the model's order.
    pub fn vector(&self, theirs: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; theirs.len()];
        for (k, &i) in self.velocity.iter().enumerate() {
            out[i] = theirs[k];
        }
        out
    }

    /// A configuration: the base's seven entries, then the joints in the model's order.
    pub fn configuration(&self, theirs: &[f64]) -> Vec<f64> {
        let mut padded = vec![0.0; 6];
        padded.extend_from_slice(&theirs[7..]);
        let mut out = theirs[..7].to_vec();
        out.extend_from_slice(&self.vector(&padded)[6..]);
        out
    }

    /// A matrix whose rows (`rows`) and/or columns (`cols`) are velocity-indexed.
    pub fn matrix(&self, theirs: &DMatrix<f64>, rows: bool, cols: bool) -> DMatrix<f64> {
        let mut out = theirs.clone();
        for r in 0..theirs.nrows() {
            for c in 0..theirs.ncols() {
                let rr = if rows { self.velocity[r] } else { r };
                let cc = if cols { self.velocity[c] } else { c };
                out[(rr, cc)] = theirs[(r, c)];
            }
        }
        out
    }

    /// A fixture matrix field with velocity-indexed rows and columns.
    pub fn square(&self, state: &Value, field: &str) -> DMatrix<f64> {
        self.matrix(&matrix(&state[field]), true, true)
    }

    /// Parameters or regressor columns in Pinocchio's body order, in the model's.
    pub fn parameter_columns(&self, theirs: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = theirs.clone();
        for (k, &b) in self.body.iter().enumerate() {
            for p in 0..10 {
                out.set_column(10 * b + p, &theirs.column(10 * k + p));
            }
        }
        out
    }
}
