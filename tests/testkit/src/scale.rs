//! Long chains and branching trees of random revolute joints, their operation counts, and the
//! scale table of TESTING.md (`cargo xtask scale`). Operation counts are deterministic (the same
//! model gives the same graph), so their growth exponent is a legitimate test, unlike a timing.

use crate::random_model::SplitMix64;
use dyngen_codegen::internals::dynamics;
use dyngen_codegen::internals::generate::{emit, trace, Provenance};
use dyngen_codegen::internals::symbolic::{record, Expr, Id};
use dyngen_codegen::model::{from_xyz_rpy, Body, Frame, Inertia, Joint, JointKind, Limits, Model, Pose};
use nalgebra::{Matrix3, Vector3};

fn unit(rng: &mut SplitMix64) -> Vector3<f64> {
    loop {
        let v = Vector3::new(
            rng.uniform((-1.0, 1.0)),
            rng.uniform((-1.0, 1.0)),
            rng.uniform((-1.0, 1.0)),
        );
        if (0.1..=1.0).contains(&v.norm()) {
            return v.normalize();
        }
    }
}

fn pose(rng: &mut SplitMix64) -> Pose {
    let angle = |rng: &mut SplitMix64| rng.uniform((-3.0, 3.0));
    from_xyz_rpy(
        [
            rng.uniform((-0.2, 0.2)),
            rng.uniform((-0.2, 0.2)),
            rng.uniform((0.05, 0.3)),
        ],
        [angle(rng), angle(rng), angle(rng)],
    )
}

fn inertia(rng: &mut SplitMix64) -> Inertia {
    // A box's principal moments (they satisfy the triangle inequality), turned at random.
    let (a, b, c) = (
        rng.uniform((0.01, 0.1)),
        rng.uniform((0.01, 0.1)),
        rng.uniform((0.01, 0.1)),
    );
    let r = pose(rng).rotation;
    Inertia {
        mass: rng.uniform((0.5, 5.0)),
        com: Vector3::new(
            rng.uniform((-0.1, 0.1)),
            rng.uniform((-0.1, 0.1)),
            rng.uniform((0.0, 0.2)),
        ),
        inertia_com: r * Matrix3::from_diagonal(&Vector3::new(b + c, a + c, a + b)) * r.transpose(),
    }
}

/// `n` revolute joints with random axes and offsets; joint `i`'s parent is `parent(i)`.
pub fn model(name: &str, n: usize, seed: u64, parent: impl Fn(usize) -> Option<usize>) -> Model {
    let mut rng = SplitMix64::new(seed);
    let joints = (0..n)
        .map(|i| Joint {
            name: format!("j{i}"),
            parent: parent(i),
            kind: JointKind::Revolute,
            origin: pose(&mut rng),
            axis: unit(&mut rng),
            limits: Some(Limits {
                lower: -2.0,
                upper: 2.0,
                velocity: 1.0,
                effort: 100.0,
            }),
        })
        .collect();
    let bodies = (0..n)
        .map(|i| Body {
            name: format!("l{i}"),
            inertia: inertia(&mut rng),
        })
        .collect();
    let end_effector = Frame {
        name: "tool".into(),
        parent: Some(n - 1),
        placement: pose(&mut rng),
    };
    Model::new(name, joints, bodies, Vector3::new(0.0, 0.0, -9.81), end_effector).expect("a valid model")
}

/// A serial chain of `n` joints.
pub fn chain(n: usize) -> Model {
    model(&format!("chain{n}"), n, 0xC4A1 + n as u64, |i| i.checked_sub(1))
}

/// Four branches of `n / 4` joints from the base (legs, fingers, arms).
pub fn tree(n: usize) -> Model {
    let per = n / 4;
    model(&format!("tree{n}"), n, 0x7EE + n as u64, move |i| {
        (i % per != 0).then(|| i - 1)
    })
}

/// Total operations (mul + add + neg + trig) of `D`, `g`, `J`, `τ`, traced alone.
pub fn op_counts(model: &Model) -> [usize; 4] {
    let n = model.dof();
    let ids = |v: &[Expr]| v.iter().map(|e| e.id()).collect::<Vec<Id>>();
    let (graph, outputs) = record(|| {
        let input = |p: &str| {
            (0..n)
                .map(|i| Expr::input(&format!("{p}{i}")))
                .collect::<Vec<_>>()
        };
        let (q, qd, a) = (input("q"), input("qd"), input("a"));
        let x = dynamics::joint_transforms(model, &q);
        let world = dynamics::body_poses(model, &x);
        let inertias = dynamics::body_inertias::<Expr>(model);
        [
            ids(dynamics::mass_matrix(model, &x, &inertias).as_slice()),
            ids(&dynamics::gravity_torque(model, &x, &inertias)),
            ids(dynamics::jacobian(model, &world).as_slice()),
            ids(&dynamics::inverse_dynamics(model, &x, &inertias, &qd, &a)),
        ]
    });
    outputs.map(|o| {
        let c = graph.op_counts(&o);
        c.mul + c.add + c.neg + c.trig
    })
}

/// Least-squares slope of `log y` against `log x`.
pub fn exponent(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|(x, y)| (x.ln(), y.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / k,
        logs.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    sxy / sxx
}

pub const NAMES: [&str; 4] = ["D", "g", "J", "τ"];

pub fn exponents(build: fn(usize) -> Model, dofs: &[usize]) -> ([f64; 4], Vec<[usize; 4]>) {
    let counts: Vec<[usize; 4]> = dofs.iter().map(|&n| op_counts(&build(n))).collect();
    let fit = std::array::from_fn(|k| {
        let points: Vec<(f64, f64)> = dofs
            .iter()
            .zip(&counts)
            .map(|(&n, c)| (n as f64, c[k] as f64))
            .collect();
        exponent(&points)
    });
    (fit, counts)
}

/// The scale table: op-count exponents, and per size the operations, generation time and code
/// size; writes the generated modules to `target/scale/` for the compile-time measurement.
pub fn report() -> String {
    use std::fmt::Write as _;
    let mut table = String::new();
    let out = crate::workspace_root().join("target/scale");
    std::fs::create_dir_all(&out).expect("target/scale");
    for (what, build, dofs) in [
        (
            "chain",
            chain as fn(usize) -> Model,
            &[5usize, 10, 15, 20, 25, 30][..],
        ),
        ("tree", tree as fn(usize) -> Model, &[8usize, 12, 16, 20][..]),
    ] {
        let (fit, counts) = exponents(build, dofs);
        let _ = writeln!(
            table,
            "{what}: op-count exponents D {:.2}, g {:.2}, J {:.2}, τ {:.2}",
            fit[0], fit[1], fit[2], fit[3]
        );
        let _ = writeln!(
            table,"| {what} DOF | D ops | g ops | J ops | τ ops | all functions ops | generation (s) | code (lines) | code (KiB) |");
        let _ = writeln!(table, "|---|---|---|---|---|---|---|---|---|");
        for (&n, c) in dofs.iter().zip(&counts) {
            let model = build(n);
            let start = std::time::Instant::now();
            let robot = trace(&model);
            let provenance = Provenance {
                source: format!("{what}{n}"),
                source_hash: "0".into(),
                regenerate: "cargo xtask scale".into(),
                type_name: format!("Scale{n}"),
            };
            let code = emit(&model, &robot, &provenance);
            let secs = start.elapsed().as_secs_f64();
            let all: usize = robot
                .quantities
                .iter()
                .map(|q| {
                    let c = robot.graph.op_counts(&q.outputs);
                    c.mul + c.add + c.neg + c.trig
                })
                .sum();
            std::fs::write(out.join(format!("{what}{n}.rs")), &code).expect("write");
            let _ = writeln!(
                table,
                "| {n} | {} | {} | {} | {} | {all} | {secs:.2} | {} | {:.0} |",
                c[0],
                c[1],
                c[2],
                c[3],
                code.lines().count(),
                code.len() as f64 / 1024.0
            );
        }
    }
    table
}
