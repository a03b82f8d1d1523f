//! A robot whose mass matrix is singular (a joint that moves no mass or inertia in its own
//! direction) is generated with a warning that names the joint: its forward dynamics do not exist.

use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::generate::generate_robot;
use dyngen_codegen::internals::dynamics::singular_joints;
use std::path::Path;

fn path(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

#[test]
fn point_mass_on_its_own_axis_warns_with_the_joint_named() {
    let file = path("tests/data/warn/singular-inertia.yaml");
    let robot = generate_robot(&file, "singular-inertia.yaml", "PointOnAxis", "test").expect("generates");
    let singular: Vec<&String> = robot
        .warnings
        .iter()
        .filter(|w| w.contains("mass matrix D is singular"))
        .collect();
    assert_eq!(singular.len(), 1, "{:#?}", robot.warnings);
    assert!(singular[0].contains("joint 'wrist'"), "{}", singular[0]);
    assert!(singular[0].contains("singular-inertia.yaml"), "{}", singular[0]);
    // The warning is true: the pivot is zero, so forward dynamics are not finite.
    let model = load(&file).expect("loads").model;
    let qdd = NumericDynamics::new(&model).forward_dynamics(&[0.3, 0.2], &[0.1, 0.1], &[1.0, 1.0]);
    assert!(qdd.iter().any(|x| !x.is_finite()), "{qdd}");
}

#[test]
fn committed_robots_have_no_singular_joint() {
    for robot in ["arm7", "panda", "panda_rounded", "ur5"] {
        let model = load(&path(&format!("../robots/{robot}.yaml")))
            .expect("loads")
            .model;
        assert_eq!(singular_joints(&model), Vec::<usize>::new(), "{robot}");
    }
}
