//! Generates each robot twice, `code_shape: flat` and `composed`, with forward dynamics and the
//! derivatives: the G1 humanoid and Solo-12 from this repository, and TIAGo Dual (101 joints)
//! when `TIAGO_DUAL_URDF` names example-robot-data's `tiago_dual.urdf`.

use dyngen_codegen::description::CodeShape;
use dyngen_codegen::{Builder, FunctionGroup};
use std::path::PathBuf;

fn generate(urdf: &PathBuf, module: &str, floating: bool, groups: &[FunctionGroup]) {
    for (shape, suffix) in [(CodeShape::Flat, "flat"), (CodeShape::Composed, "composed")] {
        let builder = Builder::new(urdf)
            .module_name(&format!("{module}_{suffix}"))
            .functions(groups)
            .code_shape(shape);
        let builder = match floating {
            true => builder.floating_base(),
            false => builder,
        };
        builder.compile_or_exit();
    }
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let both = [FunctionGroup::ForwardDynamics, FunctionGroup::Derivatives];
    let g1 = root.join("codegen/tests/data/example-robot-data/g1_description/g1_29dof_rev_1_0.urdf");
    generate(&g1, "g1", true, &both);
    generate(&root.join("robots/urdf/solo12.urdf"), "solo12", true, &both);
    println!("cargo::rustc-check-cfg=cfg(tiago)");
    println!("cargo::rerun-if-env-changed=TIAGO_DUAL_URDF");
    if let Some(tiago) = std::env::var_os("TIAGO_DUAL_URDF") {
        generate(
            &PathBuf::from(tiago),
            "tiago",
            false,
            &[FunctionGroup::ForwardDynamics],
        );
        println!("cargo::rustc-cfg=tiago");
    }
}
