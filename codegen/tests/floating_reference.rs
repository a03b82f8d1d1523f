//! Floating-base robots of example-robot-data (a quadruped and a humanoid,
//! `codegen/tests/data/example-robot-data/`) loaded with `floating_base`, against Pinocchio
//! 4.1's values for the same URDF with `JointModelFreeFlyer` (`codegen/tests/fixtures/floating/`,
//! made by `tools/floating_fixtures.py`): the base body, every dynamics quantity, frames,
//! the centroidal momentum and the configuration space's `integrate` and `difference`, joint by
//! joint name, to 1e-9 relative.

use dyngen_testkit as common;

use common::fixture::{matrix, vector};
use common::{assert_close, column, workspace_root};
use dyngen_codegen::description::{self, FrameSelection, FrameSpec, Loaded, UrdfOptions};
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_runtime::ReferenceFrame;
use nalgebra::DMatrix;
use serde_json::Value;

const TOL: f64 = 1e-9;

/// The robot as a user loads it, with the fixture's frames that ride on a moving joint.
fn load(urdf: &str, fixture: &Value) -> Loaded {
    let frames: Vec<FrameSpec> = fixture["frames"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["parent_joint"] != "root_joint")
        .map(|f| FrameSpec::link(f["name"].as_str().unwrap()))
        .collect();
    let options = UrdfOptions {
        floating_base: true,
        end_effector: Some(frames[0].clone()),
        frames: FrameSelection::Listed(frames),
        ..UrdfOptions::default()
    };
    let path = workspace_root().join("codegen/tests/data/example-robot-data").join(urdf);
    description::load_with(&path, &options).unwrap_or_else(|e| panic!("{e}"))
}

fn fixture(robot: &str) -> Value {
    let path = workspace_root().join(format!("codegen/tests/fixtures/floating/{robot}.json"));
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Index maps between Pinocchio's order and ours: `velocity[k]` is our velocity index of
/// Pinocchio's velocity entry `k` (base first, the same), `body[k]` our body block (0 the base)
/// of Pinocchio's body `k`.
struct Order {
    velocity: Vec<usize>,
    body: Vec<usize>,
}

impl Order {
    fn new(loaded: &Loaded, fixture: &Value) -> Order {
        let ours: Vec<&str> = loaded.model.joints().iter().map(|j| j.name.as_str()).collect();
        let theirs: Vec<&str> = fixture["joint_names"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap())
            .collect();
        assert_eq!(ours.len(), theirs.len(), "the moving joints");
        let joint = |name: &str| ours.iter().position(|o| *o == name).unwrap_or_else(|| panic!("joint {name}"));
        let mut velocity: Vec<usize> = (0..6).collect();
        velocity.extend(theirs.iter().map(|n| 6 + joint(n)));
        let mut body = vec![0];
        body.extend(theirs.iter().map(|n| 1 + joint(n)));
        Order { velocity, body }
    }

    /// A Pinocchio velocity-indexed vector in our order.
    fn vector(&self, theirs: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; theirs.len()];
        for (k, &i) in self.velocity.iter().enumerate() {
            out[i] = theirs[k];
        }
        out
    }

    /// A configuration: the base's seven entries, then the joints.
    fn configuration(&self, theirs: &[f64]) -> Vec<f64> {
        let mut out = theirs[..7].to_vec();
        out.extend(self.vector(&[&[0.0; 6][..], &theirs[7..]].concat())[6..].iter());
        out
    }

    /// A matrix whose rows (`rows`) and/or columns (`cols`) are velocity-indexed.
    fn matrix(&self, theirs: &DMatrix<f64>, rows: bool, cols: bool) -> DMatrix<f64> {
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

    /// Parameters or regressor columns in Pinocchio's body order, in ours.
    fn parameter_columns(&self, theirs: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = theirs.clone();
        for (k, &b) in self.body.iter().enumerate() {
            for p in 0..10 {
                out.set_column(10 * b + p, &theirs.column(10 * k + p));
            }
        }
        out
    }
}

fn check_robot(robot: &str, urdf: &str) {
    let fx = fixture(robot);
    let loaded = load(urdf, &fx);
    let model = &loaded.model;
    assert_eq!(model.floating_base().unwrap().name, fx["base_body"].as_str().unwrap());
    assert_eq!((model.nq(), model.nv()), (fx["nq"].as_u64().unwrap() as usize, fx["nv"].as_u64().unwrap() as usize));
    let order = Order::new(&loaded, &fx);
    let dynamics = FloatingDynamics::new(model).unwrap();
    let pi = DMatrix::from_row_slice(1, vector(&fx["pi"]).len(), &vector(&fx["pi"]));
    assert_close(
        &format!("{robot}: parameters (base first)"),
        &DMatrix::from_row_slice(1, pi.ncols(), &dynamics.parameters()),
        &order.parameter_columns(&pi),
        TOL,
    );
    let states = fx["states"].as_array().unwrap();
    for (k, st) in states.iter().enumerate() {
        let what = |q: &str| format!("{robot} state {k}: {q}");
        let q = order.configuration(&vector(&st["q"]));
        let [v, a, vr, ar] = ["v", "a", "vr", "ar"].map(|f| order.vector(&vector(&st[f])));
        let reorder = |f: &str| order.matrix(&matrix(&st[f]), true, true);
        let rows = |f: &str| column(&order.vector(&vector(&st[f])));
        let s = dynamics.state(&q).unwrap();
        assert_close(&what("D"), &dynamics.mass_matrix(&s), &reorder("D"), TOL);
        assert_close(&what("C"), &dynamics.coriolis_matrix(&s, &v), &reorder("C"), TOL);
        assert_close(&what("g"), &column(dynamics.gravity(&s).as_slice()), &rows("g"), TOL);
        let tau = dynamics.inverse_dynamics(&s, &v, &a);
        assert_close(&what("tau"), &column(tau.as_slice()), &rows("tau"), TOL);
        assert_close(
            &what("tau_ref"),
            &column(dynamics.slotine_li(&s, &v, &vr, &ar).as_slice()),
            &rows("tau_ref"),
            TOL,
        );
        let y = order.parameter_columns(&order.matrix(&matrix(&st["Y"]), true, false));
        assert_close(&what("Y"), &dynamics.regressor(&s, &v, &v, &a), &y, TOL);
        assert_close(
            &what("aba"),
            &column(dynamics.forward_dynamics(&s, &v, tau.as_slice()).as_slice()),
            &rows("aba"),
            TOL,
        );
        assert_close(&what("Minv"), &dynamics.mass_matrix_inverse(&s), &reorder("Minv"), TOL);
        let (mass, com, ag) = dynamics.centroidal_momentum_matrix(&s);
        assert!(mass > 0.0);
        assert_close(&what("com"), &column(com.as_slice()), &column(&vector(&st["com"])), TOL);
        assert_close(&what("Ag"), &ag, &order.matrix(&matrix(&st["Ag"]), false, true), TOL);
        assert_close(
            &what("Jcom"),
            &dynamics.center_of_mass_jacobian(&s),
            &order.matrix(&matrix(&st["Jcom"]), false, true),
            TOL,
        );
        assert_close(
            &what("dAg_v"),
            &column(dynamics.centroidal_bias(&s, &v).as_slice()),
            &column(&vector(&st["dAg_v"])),
            TOL,
        );
        let mut frames_compared = 0;
        for (f, frame) in st["frames"].as_object().unwrap() {
            let Some(index) = model.frames().iter().position(|m| m.name == *f) else {
                continue; // a frame on the base body
            };
            frames_compared += 1;
            let (rotation, translation) = dynamics.frame_pose(&s, index);
            assert_close(&what(&format!("{f} translation")), &column(translation.as_slice()), &column(&vector(&frame["translation"])), TOL);
            assert_close(&what(&format!("{f} rotation")), &DMatrix::from_column_slice(3, 3, rotation.as_slice()), &matrix(&frame["rotation"]), TOL);
            let columns = |field: &str| order.matrix(&matrix(&frame[field]), false, true);
            let lwa = ReferenceFrame::LocalWorldAligned;
            assert_close(&what(&format!("{f} J")), &dynamics.frame_jacobian(&s, index, lwa), &columns("J_lwa"), TOL);
            assert_close(
                &what(&format!("{f} J local")),
                &dynamics.frame_jacobian(&s, index, ReferenceFrame::Local),
                &columns("J_local"),
                TOL,
            );
            assert_close(
                &what(&format!("{f} Jdot")),
                &dynamics.frame_jacobian_time_variation(&s, &v, index, lwa),
                &columns("Jdot_lwa"),
                TOL,
            );
        }
        assert!(frames_compared >= 4, "{}", what("the feet (and hands) compared"));
        let moved = dynamics.integrate(&q, &v, 0.1).unwrap();
        assert_close(&what("integrate"), &column(&moved), &column(&order.configuration(&vector(&st["integrate"]))), TOL);
        let next = order.configuration(&vector(&states[(k + 1) % states.len()]["q"]));
        let difference = dynamics.difference(&q, &next).unwrap();
        assert_close(&what("difference"), &column(&difference), &column(&order.vector(&vector(&st["difference"]))), TOL);
    }
}

#[test]
fn quadruped_matches_pinocchio() {
    check_robot("solo12", "solo_description/solo12.urdf");
}

#[test]
fn humanoid_matches_pinocchio() {
    check_robot("g1", "g1_description/g1_29dof_rev_1_0.urdf");
}
