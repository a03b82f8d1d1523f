//! Pinocchio 4.1's values for named frames and external wrenches
//! (`codegen/tests/fixtures/frames/`, made by `tools/frame_fixtures.py`): every link frame of the
//! Panda and the UR5 in the three reference frames, and `rnea`/`aba` with wrenches at frames.

use crate::fixture::{matrix, vector};
use dyngen_runtime::ReferenceFrame;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use serde_json::Value;

/// One frame at one state.
pub struct FrameState {
    pub name: String,
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
    /// `J`, `J̇`, velocity and classical acceleration, indexed like [`ReferenceFrame::ALL`].
    pub jacobian: [DMatrix<f64>; 3],
    pub jacobian_time_variation: [DMatrix<f64>; 3],
    pub velocity: [Vector6<f64>; 3],
    pub classical_acceleration: [Vector6<f64>; 3],
}

/// A wrench at a frame: `[force; moment]` in `reference`.
pub struct Wrench {
    pub frame: String,
    pub reference: ReferenceFrame,
    pub wrench: Vector6<f64>,
}

pub struct State {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    /// Every frame that moves with a joint (frames welded to the base are left out: dyngen
    /// generates no functions for them).
    pub frames: Vec<FrameState>,
    pub wrenches: Vec<Wrench>,
    /// `rnea(q, v, a, fext)`.
    pub tau_fext: DVector<f64>,
    /// `aba(q, v, tau_aba, fext)`.
    pub tau_aba: DVector<f64>,
    pub qdd_fext: DVector<f64>,
}

fn six(v: &Value) -> Vector6<f64> {
    Vector6::from_vec(vector(v))
}

fn per_reference<T>(v: &Value, f: impl Fn(&Value) -> T) -> [T; 3] {
    ReferenceFrame::ALL.map(|r| f(&v[r.keyword()]))
}

/// The states of `codegen/tests/fixtures/frames/<robot>.json`.
pub fn load(robot: &str) -> Vec<State> {
    let path = format!(
        "{}/../../codegen/tests/fixtures/frames/{robot}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("frame fixture file")).expect("json");
    let moving: Vec<&str> = json["frames"]
        .as_array()
        .expect("frames")
        .iter()
        .filter(|f| f["parent_joint"] != "universe")
        .map(|f| f["name"].as_str().expect("name"))
        .collect();
    json["states"]
        .as_array()
        .expect("states")
        .iter()
        .map(|s| State {
            q: vector(&s["q"]),
            v: vector(&s["v"]),
            a: vector(&s["a"]),
            frames: moving
                .iter()
                .map(|&name| {
                    let f = &s["frames"][name];
                    let r = matrix(&f["rotation"]);
                    FrameState {
                        name: name.to_owned(),
                        rotation: Matrix3::from_fn(|i, j| r[(i, j)]),
                        translation: Vector3::from_vec(vector(&f["translation"])),
                        jacobian: per_reference(&f["J"], matrix),
                        jacobian_time_variation: per_reference(&f["dJ"], matrix),
                        velocity: per_reference(&f["velocity"], six),
                        classical_acceleration: per_reference(&f["classical_acceleration"], six),
                    }
                })
                .collect(),
            wrenches: s["wrenches"]
                .as_array()
                .expect("wrenches")
                .iter()
                .map(|w| Wrench {
                    frame: w["frame"].as_str().expect("frame").to_owned(),
                    reference: ReferenceFrame::ALL
                        .into_iter()
                        .find(|r| r.keyword() == w["reference"])
                        .expect("a reference frame"),
                    wrench: six(&w["wrench"]),
                })
                .collect(),
            tau_fext: DVector::from_vec(vector(&s["tau_fext"])),
            tau_aba: DVector::from_vec(vector(&s["tau_aba"])),
            qdd_fext: DVector::from_vec(vector(&s["qdd_fext"])),
        })
        .collect()
}
