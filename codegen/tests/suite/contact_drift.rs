//! The contacts' drift as a floating base generates it, from the bodies' motions of the bias
//! pass (`trace_floating.rs`), against the `f64` dynamics' drift from each frame's `J̇`
//! (`FloatingDynamics::contact_drift`): on random trees (light links, heavy tools), with a
//! contact at a frame placed anywhere on a random body and one at a frame on the base body,
//! held to the world or to another body's frame (a loop), point or frame, in either axes.

use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_codegen::internals::generate::{trace, Arguments};
use dyngen_codegen::model::{Contact, Frame};
use dyngen_runtime::{ContactKind, ReferenceFrame};
use dyngen_testkit::random_model::{
    arb_floating_model, arb_pose, deterministic_runner, random_floating_sample,
};
use nalgebra::DVector;
use proptest::prelude::*;
use proptest::sample::Index;

/// Relative to the drift's size: two formulations of the same sums.
const TOL: f64 = 1e-10;

fn kind(frame: bool) -> ContactKind {
    match frame {
        true => ContactKind::Frame,
        false => ContactKind::Point,
    }
}

fn reference(local: bool) -> ReferenceFrame {
    match local {
        true => ReferenceFrame::Local,
        false => ReferenceFrame::LocalWorldAligned,
    }
}

#[test]
fn the_drift_from_the_bias_pass_is_the_drift_from_the_frames_rates() {
    let strategy = (
        arb_floating_model(5),
        (arb_pose(), arb_pose(), any::<Index>(), any::<Index>()),
        (any::<[bool; 2]>(), any::<[bool; 2]>(), any::<bool>()),
    );
    let checked = std::cell::Cell::new(0);
    deterministic_runner(48)
        .run(
            &strategy,
            |(model, (on_body, on_base, body, other), (frames, locals, looped))| {
                let n = model.joints().len();
                let mut all: Vec<Frame> = model.frames().to_vec();
                all.push(Frame {
                    name: "on_body".into(),
                    parent: Some(body.index(n)),
                    placement: on_body,
                });
                all.push(Frame {
                    name: "on_base".into(),
                    parent: None,
                    placement: on_base,
                });
                let model = model.with_frames(all).expect("valid frames");
                let index = |name: &str| model.frames().iter().position(|f| f.name == name).unwrap();
                // The base frame's contact is held to the world, or to a frame on another body.
                let to = looped.then(|| index(&format!("origin{}", other.index(n))));
                let contacts = vec![
                    Contact {
                        frame: index("on_body"),
                        kind: kind(frames[0]),
                        reference: reference(locals[0]),
                        to: None,
                    },
                    Contact {
                        frame: index("on_base"),
                        kind: kind(frames[1]),
                        reference: reference(locals[1]),
                        to,
                    },
                ];
                // A set that holds the whole robot still is refused by the model.
                let Ok(model) = model.with_contacts(contacts.clone()) else {
                    return Ok(());
                };
                let traced = trace(&model);
                let dynamics = FloatingDynamics::new(&model).expect("a floating base");
                for seed in 0..3 {
                    let sample = random_floating_sample(&model, seed);
                    let state = dynamics.state(&sample.q).expect("a unit quaternion");
                    let expected = dynamics
                        .contact_drift(&state, &sample.v, &contacts)
                        .expect("valid contacts");
                    let args = Arguments {
                        q: &sample.q,
                        qd: &sample.v,
                        ..Arguments::default()
                    };
                    let generated = DVector::from_vec(traced.evaluate_with("contact_drift", &args).unwrap());
                    let error = (&generated - &expected).amax() / expected.amax().max(1.0);
                    prop_assert!(
                        error <= TOL,
                        "error {error:.2e}\ngenerated {generated:.6}\nfrom J̇ {expected:.6}"
                    );
                }
                checked.set(checked.get() + 1);
                Ok(())
            },
        )
        .unwrap();
    // Most sets leave the robot free to move: the test compared something.
    let checked = checked.get();
    assert!(checked >= 24, "only {checked} of 48 contact sets were valid");
}
