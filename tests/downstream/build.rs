fn main() {
    dyngen_codegen::compile_robot("../../robots/panda.yaml");
    // A robot with mimic joints (revolute, multipliers 1.5 and −1 with offsets): its generated
    // code compiles with `#![deny(warnings)]` and is tested against the generic dynamics.
    dyngen_codegen::compile_robot("../../codegen/tests/data/mimic/mimic_arm.yaml");
    // A bare URDF on a floating base, chosen by the builder (no YAML): a quadruped.
    dyngen_codegen::Builder::new("../../robots/urdf/solo12.urdf")
        .floating_base()
        .module_name("quadruped")
        .compile_or_exit();
    // Floating bases with mimic joints (a gripper's fingers) and with joint friction and
    // armature: generated, compiled, and tested against the generic dynamics.
    dyngen_codegen::compile_robot("../../codegen/tests/data/mimic/floating_gripper.yaml");
    dyngen_codegen::compile_robot("../../codegen/tests/data/floating/hopper_friction.yaml");
}
