//! Generates the G1 with its derivatives (`g1.yaml`) into `OUT_DIR`.

fn main() {
    dyngen_codegen::Builder::new("g1.yaml")
        .module_name("g1")
        .type_name("G1")
        .compile_or_exit();
}
