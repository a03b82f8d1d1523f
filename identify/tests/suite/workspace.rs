//! Workspace constraints of an excitation: on arm7 and the Panda, regions that the
//! unconstrained optimum leaves are kept along the whole constrained trajectory (checked at
//! ten times the density of the proof's grid, through another kinematics path), the result
//! is still well conditioned, and impossible or malformed constraints are errors.

use crate::common;

use common::arm7_nominal;
use dyngen_identify::{
    optimise, optimise_within, BaseModel, ExcitationError, ExcitationOptions, FourierTrajectory, Region,
    TrajectoryLimits, Workspace, WorkspaceConstraint, DEFAULT_ACCELERATION_PER_VELOCITY,
};
use dyngen_model::description::load;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::Model;
use nalgebra::Vector3;
use std::path::Path;

fn panda() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda.yaml");
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

fn options() -> ExcitationOptions {
    ExcitationOptions {
        samples: 100,
        starts: 4,
        iterations: 60,
        ..ExcitationOptions::default()
    }
}

/// The smallest margin of each constraint over `points` times of one period, the frame's
/// position from `frame_motion` (not the body poses the check uses).
fn smallest_margins(
    model: &Model,
    t: &FourierTrajectory,
    constraints: &[WorkspaceConstraint],
    points: usize,
) -> Vec<f64> {
    let dynamics = NumericDynamics::new(model);
    let mut worst = vec![f64::INFINITY; constraints.len()];
    for k in 0..points {
        let s = t.at(t.period() * k as f64 / points as f64);
        for (c, w) in constraints.iter().zip(worst.iter_mut()) {
            let frame = dynamics.frame_motion(&c.frame, &s.q, &s.qd).expect("frame");
            *w = w.min(c.region.margin(&frame.pose().1));
        }
    }
    worst
}

/// Unconstrained, then constrained: the unconstrained optimum leaves a region, the constrained
/// one stays in every region at 10 × 64 points per harmonic and period, with its condition
/// number within `factor` of the unconstrained one's.
fn constrained_against_unconstrained(model: &Model, constraints: &[WorkspaceConstraint], factor: f64) {
    let base = BaseModel::new(model);
    let limits = TrajectoryLimits::from_model(model, DEFAULT_ACCELERATION_PER_VELOCITY);
    let options = options();
    let dense = 10 * 64 * options.harmonics;
    let free = optimise(&base, &limits, &options);
    let free_margins = smallest_margins(model, &free.trajectory, constraints, dense);
    let workspace = Workspace::new(model, constraints).expect("valid constraints");
    let kept = optimise_within(&base, &limits, &workspace, &options).unwrap_or_else(|e| panic!("{e}"));
    let kept_margins = smallest_margins(model, &kept.trajectory, constraints, dense);
    let check = kept.workspace.as_ref().expect("a workspace check");
    println!(
        "{}: unconstrained condition number {:.1} (random {:.1}), smallest margins {:?} m; \
         constrained {:.1} (random {:.1}), smallest margins {:?} m; proof: {} evaluations, \
         speed bound {:.2} m/s, guaranteed margin {:.2e} m",
        model.name(),
        free.condition_number,
        free.random_condition_number,
        free_margins,
        kept.condition_number,
        kept.random_condition_number,
        kept_margins,
        check.evaluations,
        check.speed_bound,
        check.guaranteed_margin
    );
    assert!(
        free_margins.iter().any(|&m| m < 0.0),
        "the unconstrained optimum already satisfies the constraints: the test proves nothing"
    );
    assert!(check.inside && check.guaranteed_margin >= 0.0);
    for (c, m) in constraints.iter().zip(&kept_margins) {
        assert!(*m >= check.guaranteed_margin, "{}: margin {m}", c.frame);
    }
    let times: Vec<f64> = (0..dense)
        .map(|k| kept.trajectory.period() * k as f64 / dense as f64)
        .collect();
    assert_eq!(kept.trajectory.check_limits(&limits, &times), Ok(()));
    assert!(
        kept.condition_number <= factor * free.condition_number,
        "constrained condition number {} against {}",
        kept.condition_number,
        free.condition_number
    );
}

/// arm7's flange in a box in front of and above the base (a cell whose floor is 0.4 m high).
#[test]
fn arm7_flange_in_a_box() {
    let model = arm7_nominal();
    let constraints = [WorkspaceConstraint {
        frame: "flange".into(),
        region: Region::Box {
            min: Vector3::new(-0.8, -0.8, 0.4),
            max: Vector3::new(0.8, 0.8, 1.5),
        },
    }];
    constrained_against_unconstrained(&model, &constraints, 3.0);
}

/// A box in front of arm7 that the upright middle posture is outside of: the search starts
/// from a posture inside it instead, and stays inside.
#[test]
fn arm7_flange_in_a_box_away_from_the_middle_posture() {
    let model = arm7_nominal();
    let base = BaseModel::new(&model);
    let limits = TrajectoryLimits::from_model(&model, DEFAULT_ACCELERATION_PER_VELOCITY);
    let constraints = [WorkspaceConstraint {
        frame: "flange".into(),
        region: Region::between([0.3, -0.5, 0.2], [0.9, 0.5, 1.0]),
    }];
    let workspace = Workspace::new(&model, &constraints).expect("valid");
    let e = optimise_within(&base, &limits, &workspace, &options()).unwrap_or_else(|e| panic!("{e}"));
    let margins = smallest_margins(&model, &e.trajectory, &constraints, 10 * 64 * 5);
    println!(
        "arm7 in front: condition number {:.1} (random {:.1}), smallest margin {:.4} m, centre {:?}",
        e.condition_number, e.random_condition_number, margins[0], e.trajectory.offsets
    );
    assert!(
        e.trajectory.offsets.iter().any(|q| q.abs() > 0.1),
        "{:?}",
        e.trajectory.offsets
    );
    assert!(margins[0] >= 0.0, "{margins:?}");
    assert!(e.condition_number.is_finite());
}

/// The Panda's hand above a table 0.3 m high and its elbow (link 4) on one side of a wall.
#[test]
fn panda_hand_above_a_table_and_elbow_off_a_wall() {
    let model = panda();
    let constraints = [
        WorkspaceConstraint {
            frame: model.end_effector().name.clone(),
            region: Region::Above {
                normal: Vector3::new(0.0, 0.0, 1.0),
                offset: 0.3,
            },
        },
        WorkspaceConstraint {
            frame: "panda_link4".into(),
            region: Region::Above {
                normal: Vector3::new(0.0, -1.0, 0.0),
                offset: -0.25,
            },
        },
    ];
    constrained_against_unconstrained(&model, &constraints, 3.0);
}

/// A region no posture reaches, an empty box, a zero normal and an unknown frame are errors
/// that say which.
#[test]
fn impossible_and_malformed_constraints_are_errors() {
    let model = arm7_nominal();
    let base = BaseModel::new(&model);
    let limits = TrajectoryLimits::from_model(&model, DEFAULT_ACCELERATION_PER_VELOCITY);
    let above = |offset: f64| WorkspaceConstraint {
        frame: "flange".into(),
        region: Region::Above {
            normal: Vector3::new(0.0, 0.0, 1.0),
            offset,
        },
    };
    let out_of_reach = Workspace::new(&model, &[above(2.0)]).expect("valid");
    let err = optimise_within(&base, &limits, &out_of_reach, &options()).expect_err("out of reach");
    assert!(matches!(err, ExcitationError::Infeasible(_)), "{err}");
    assert!(err.to_string().contains("flange"), "{err}");

    let empty = WorkspaceConstraint {
        frame: "flange".into(),
        region: Region::Box {
            min: Vector3::new(0.0, 0.0, 1.0),
            max: Vector3::new(0.5, 0.5, 0.9),
        },
    };
    let err = Workspace::new(&model, &[empty]).expect_err("empty box");
    assert!(err.to_string().contains("empty along z"), "{err}");

    let flat = WorkspaceConstraint {
        frame: "flange".into(),
        region: Region::Above {
            normal: Vector3::zeros(),
            offset: 0.0,
        },
    };
    assert!(matches!(
        Workspace::new(&model, &[flat]),
        Err(ExcitationError::ZeroNormal { .. })
    ));

    let unknown = WorkspaceConstraint {
        frame: "gripper".into(),
        ..above(0.0)
    };
    let err = Workspace::new(&model, &[unknown]).expect_err("unknown frame");
    assert_eq!(
        err.to_string(),
        "the robot has no frame 'gripper'; its frames: flange"
    );
}

/// The check is a proof, not a sample: a plane that the frame touches only between two
/// points of a coarse grid is found.
#[test]
fn the_check_finds_a_violation_between_grid_points() {
    let model = arm7_nominal();
    let dynamics = NumericDynamics::new(&model);
    let limits = TrajectoryLimits::from_model(&model, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, 11);
    t.fit_into(&limits);
    // The lowest height of the flange on a fine grid, and the time.
    let points = 20_000;
    let (mut low, mut at) = (f64::INFINITY, 0.0);
    for k in 0..points {
        let time = t.period() * k as f64 / points as f64;
        let z = dynamics.end_effector_pose(&t.at(time).q).1.z;
        if z < low {
            (low, at) = (z, time);
        }
    }
    // A plane just below that minimum is kept; just above it, it is left near `at`, which a
    // grid of 7 points does not contain.
    let plane = |offset: f64| {
        Workspace::new(
            &model,
            &[WorkspaceConstraint {
                frame: "flange".into(),
                region: Region::Above {
                    normal: Vector3::z(),
                    offset,
                },
            }],
        )
        .expect("valid")
    };
    let below = plane(low - 1e-3).check(&dynamics, &t, 7, false);
    assert!(below.inside, "{below:?}");
    let above = plane(low + 1e-4).check(&dynamics, &t, 7, false);
    assert!(!above.inside, "{above:?}");
    assert!(
        (above.time - at).abs() < 0.05 * t.period(),
        "{above:?}, lowest at {at}"
    );
    println!(
        "below: {} evaluations; above: found at {:.4} s (lowest at {at:.4} s) after {} evaluations",
        below.evaluations, above.time, above.evaluations
    );
}
