//! What the solves read in one call (`contact_delassus`, `contact_matrices`, `contact_system`),
//! evaluated by the interpreter: the Delassus matrix `K` (traced from the factored mass matrix,
//! `Yᵀ Δ⁻¹ Y`) is `J M⁻¹ Jᵀ` of the traced rows to rounding and exactly symmetric, and every
//! other part is the row it repeats, to the bit (the same nodes). On a floating base (Solo-12's
//! four point feet), a fixed-base chain holding its tool and a point halfway up (the
//! Panda, whose rows share a branch), two branches held tip to tip (frame loops) and the
//! four-bar, whose rows are dependent (`K` singular, still `J M⁻¹ Jᵀ`).

use dyngen_testkit as common;

use common::{assert_close, workspace_root};
use dyngen_codegen::description::load;
use dyngen_codegen::internals::generate::{trace, Arguments};
use dyngen_codegen::model::{Contact, Model};
use dyngen_runtime::{ContactKind, ReferenceFrame, SplitMix64};
use nalgebra::DMatrix;

/// `K` against `J M⁻¹ Jᵀ`, relative to its largest entry.
const TOL: f64 = 1e-12;

/// Checks the three rows at `states` random states of `model` (`floating`: its configuration
/// starts with a base position and a unit quaternion).
fn check(robot: &str, model: &Model, floating: bool, states: usize) {
    let traced = trace(model);
    let (nv, nc) = (model.nv(), model.contact_rows());
    let nq = if floating { nv + 1 } else { nv };
    let mut rng = SplitMix64::new(nv as u64 * 31 + nc as u64);
    for k in 0..states {
        let what = |q: &str| format!("{robot} state {k}: {q}");
        let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform((-3.0, 3.0))).collect();
        if floating {
            let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            q[3..7].iter_mut().for_each(|x| *x /= norm);
        }
        let [v, tau] = [0; 2].map(|_| (0..nv).map(|_| rng.uniform((-4.0, 4.0))).collect::<Vec<f64>>());
        let args = Arguments {
            q: &q,
            qd: &v,
            tau: &tau,
            ..Arguments::default()
        };
        let value = |name: &str| traced.evaluate_with(name, &args).expect(name);
        let system = value("contact_system");
        let matrices = value("contact_matrices");
        let delassus = value("contact_delassus");
        // The parts in their order: J, M⁻¹ Jᵀ, K, then the drift and the free acceleration.
        let (jacobian, rest) = system.split_at(nc * nv);
        let (response, rest) = rest.split_at(nv * nc);
        let (k, rest) = rest.split_at(nc * nc);
        let (drift, free) = rest.split_at(nc);
        assert_eq!(
            &system[..matrices.len()],
            matrices.as_slice(),
            "{}",
            what("matrices")
        );
        assert_eq!(k, delassus.as_slice(), "{}", what("K alone"));
        assert_eq!(jacobian, value("contact_jacobian").as_slice(), "{}", what("J"));
        assert_eq!(
            response,
            value("contact_response").as_slice(),
            "{}",
            what("M⁻¹ Jᵀ")
        );
        assert_eq!(drift, value("contact_drift").as_slice(), "{}", what("drift"));
        assert_eq!(
            free,
            value("forward_dynamics").as_slice(),
            "{}",
            what("free acceleration")
        );
        let k = DMatrix::from_column_slice(nc, nc, k);
        assert_eq!(k, k.transpose(), "{}", what("K symmetric"));
        let product =
            DMatrix::from_column_slice(nc, nv, jacobian) * DMatrix::from_column_slice(nv, nc, response);
        assert_close(&what("K = J M⁻¹ Jᵀ"), &k, &product, TOL);
    }
}

fn robot(name: &str) -> Model {
    let path = workspace_root().join("robots").join(format!("{name}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

#[test]
fn solo12_on_four_point_feet() {
    check("solo12", &robot("solo12"), true, 20);
}

#[test]
fn a_chain_holding_its_tool_and_a_point_halfway_up() {
    let panda = robot("panda");
    let contacts = vec![
        Contact::at(
            &panda,
            "panda_hand_tcp",
            ContactKind::Point,
            ReferenceFrame::LocalWorldAligned,
        )
        .unwrap(),
        Contact::at(&panda, "panda_link4", ContactKind::Point, ReferenceFrame::Local).unwrap(),
    ];
    check("panda", &panda.with_contacts(contacts).unwrap(), false, 20);
}

#[test]
fn loops_and_dependent_rows() {
    for name in ["two_branches", "four_bar"] {
        let fx = crate::loop_closures::fixture(name);
        for (k, _) in fx["sets"].as_array().unwrap().iter().enumerate() {
            let loaded = crate::loop_closures::load(name, &fx);
            let contacts = common::floating_fixture::contacts(&loaded.model, &fx["sets"][k]);
            let model = loaded.model.with_contacts(contacts).unwrap();
            check(&format!("{name} set {k}"), &model, false, 10);
        }
    }
}
