//! Generated code keeps the promises a control loop relies on: no `unsafe`, no allocation, no
//! panic path. The allocation check runs every generated function under a counting allocator.

use dyngen_generated::{Arm7, Arm7Friction, Panda, PandaRounded, Ur5};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{DynamicsDerivatives, ForwardDynamics, JointTrig, Regressors};
use dyngen_testkit::allocations::{allocations, CountingAllocator};
use std::hint::black_box;
use std::path::Path;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn every_function<
    R: Regressors<N, P> + ForwardDynamics<N, P> + DynamicsDerivatives<N, P>,
    const N: usize,
    const P: usize,
>() {
    let q = SVector::<f64, N>::from_fn(|i, _| 0.3 * i as f64 - 1.0);
    let (qd, v, a) = (q * 0.5, q * -0.2, q * 1.5);
    let t = JointTrig::new(&q);
    black_box(R::parameters());
    black_box(R::forward_kinematics(&t));
    black_box(R::jacobian(&t));
    black_box(R::jacobian_dot(&t, &qd));
    black_box(R::mass_matrix(&t));
    black_box(R::coriolis_matrix(&t, &qd));
    black_box(R::gravity(&t));
    black_box(R::inverse_dynamics(&t, &qd, &a));
    black_box(R::slotine_li(&t, &qd, &v, &a));
    black_box(R::regressor(&t, &qd, &v, &a));
    black_box(R::torque_regressor(&t, &qd, &a));
    black_box(R::kinematics(&t, &qd));
    black_box(R::forward_dynamics(&t, &qd, &a));
    black_box(R::mass_matrix_inverse(&t));
    black_box(R::inverse_dynamics_derivatives(&t, &qd, &a));
    black_box(R::forward_dynamics_derivatives(&t, &qd, &a));
}

#[test]
fn the_counting_allocator_sees_an_allocation() {
    // Without this, a broken counter would make the test below pass vacuously.
    assert!(allocations(|| drop(black_box(vec![1.0_f64; 8]))) >= 1);
}

#[test]
fn generated_functions_do_not_allocate() {
    assert_eq!(allocations(every_function::<Arm7, 7, 70>), 0, "arm7");
    assert_eq!(
        allocations(every_function::<Arm7Friction, 7, 98>),
        0,
        "arm7_friction"
    );
    assert_eq!(allocations(every_function::<Panda, 7, 70>), 0, "panda");
    assert_eq!(
        allocations(every_function::<PandaRounded, 7, 70>),
        0,
        "panda_rounded"
    );
    assert_eq!(allocations(every_function::<Ur5, 6, 60>), 0, "ur5");
}

#[test]
fn generated_sources_have_no_unsafe_allocation_or_panic_path() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("generated/src");
    // Whole tokens (identifiers and macro names), so that `SVector` is not `Vec`.
    let forbidden = [
        "unsafe",
        "Vec",
        "vec!",
        "Box",
        "String",
        "format!",
        "unwrap",
        "expect",
        "panic!",
        "unreachable!",
        "todo!",
        "get",
    ];
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).expect("generated/src") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "rs") && path.file_name() != Some("lib.rs".as_ref()) {
            files += 1;
            let code = std::fs::read_to_string(&path).expect("readable");
            let tokens: std::collections::BTreeSet<&str> = code
                .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '!'))
                .collect();
            for word in forbidden {
                assert!(!tokens.contains(word), "{}: contains `{word}`", path.display());
            }
        }
    }
    assert!(files >= 3, "found the generated robots");
}

/// The text of the trait method `name` in `code`, up to the next item.
fn method<'a>(code: &'a str, name: &str) -> &'a str {
    let start = code.find(&format!("    fn {name}(")).expect("the function");
    let body = &code[start..];
    &body[..body[1..].find("\n    fn ").map_or(body.len(), |end| end + 1)]
}

/// `(vector, lane, entry)` of every lane stored on its own (`[_, x5, _, _] = x3.to_array();`
/// followed by `*o17 = x5;`) in `body`.
fn lanes_stored_one_by_one(body: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = body.lines().map(str::trim).collect();
    let mut stores = Vec::new();
    for pair in lines.windows(2) {
        let Some((pattern, vector)) = pair[0]
            .strip_suffix(".to_array();")
            .and_then(|s| s.split_once("] = "))
        else {
            continue;
        };
        let lanes: Vec<&str> = pattern.trim_start_matches('[').split(", ").collect();
        let Some(lane) = lanes.iter().position(|&l| l != "_") else {
            continue;
        };
        let store = format!("= {};", lanes[lane]);
        if let Some(entry) = pair[1]
            .strip_prefix("*o")
            .and_then(|s| s.strip_suffix(store.as_str()))
        {
            let entry: usize = entry.trim().parse().expect("an output index");
            stores.push((vector.to_string(), lane, entry));
        }
    }
    stores
}

/// Four lanes of one vector bound for four consecutive entries of one column are stored as one
/// vector (`*g14 = x3.to_array();`): stored lane by lane, LLVM joins the run into 512-bit stores
/// and shuffles in a default build's AVX-512 copy, which made the arms' regressors slower than
/// in a native build (`docs/performance-notes.md`).
#[test]
fn four_lanes_bound_for_one_column_are_stored_as_one_vector() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("generated/src");
    for (file, rows) in [("panda.rs", 7), ("ur5.rs", 6), ("xarm7.rs", 7)] {
        let code = std::fs::read_to_string(dir.join(file)).expect("readable");
        for name in [
            "regressor",
            "torque_regressor",
            "base_regressor",
            "base_torque_regressor",
        ] {
            let body = method(&code, name);
            let stores = lanes_stored_one_by_one(body);
            let whole = |&(ref v, lane, entry): &(String, usize, usize)| {
                lane == 0
                    && entry % rows + 4 <= rows
                    && (1..4).all(|k| stores.contains(&(v.clone(), k, entry + k)))
            };
            assert!(
                !stores.iter().any(whole),
                "{file} {name}: a vector stored lane by lane"
            );
            assert!(body.contains(" @ .."), "{file} {name}: no vector stored whole");
        }
    }
}
