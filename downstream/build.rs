fn main() {
    dyngen_codegen::compile_robot("../robots/panda.yaml");
}
