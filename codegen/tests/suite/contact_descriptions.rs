//! `contacts:` in a description: the frames it holds resolved against the model's named
//! frames, in order, with their kinds and axes; each mistake one error at its place.

use dyngen_codegen::description::{self, ContactSpec};
use dyngen_codegen::dynamics::constrained::free_degrees;
use dyngen_codegen::Builder;
use dyngen_runtime::{ContactKind, ReferenceFrame};
use std::path::Path;

/// A four-joint arm with two named frames besides its tip; `contacts` is appended (its first
/// line is line 15).
fn arm(contacts: &str) -> String {
    let joint = |name: &str, parent: &str, child: &str, z: f64| {
        format!(
            "  - {{ name: {name}, type: revolute, parent: {parent}, child: {child}, origin: {{ xyz: [0.0, 0.0, {z}] }}, \
             axis: [0.0, 1.0, 0.0], limit: {{ lower: -3.0, upper: 3.0, velocity: 2.0, effort: 50.0 }} }}\n"
        )
    };
    let link = |name: &str| {
        format!(
            "  - {{ name: {name}, inertial: {{ mass: 1.0, inertia: {{ ixx: 0.01, ixy: 0.0, ixz: 0.0, iyy: 0.01, iyz: 0.0, izz: 0.01 }} }} }}\n"
        )
    };
    format!(
        "name: arm\nend_effector: {{ name: tip, link: d, xyz: [0.0, 0.0, 0.2] }}\nframes: [b, c]\nlinks:\n  - name: base\n{}{}{}{}joints:\n{}{}{}{}{}",
        link("a"),
        link("b"),
        link("c"),
        link("d"),
        joint("j1", "base", "a", 0.0),
        joint("j2", "a", "b", 0.3),
        joint("j3", "b", "c", 0.3),
        joint("j4", "c", "d", 0.3),
        contacts
    )
}

fn load(text: &str) -> Result<description::Loaded, String> {
    description::load_yaml_str(text, Path::new("arm.yaml")).map_err(|e| e.to_string())
}

#[test]
fn contacts_are_resolved_in_order_with_their_kinds_and_axes() {
    let loaded = load(&arm("contacts:\n  - { frame: tip, kind: point }\n")).unwrap();
    let contacts = loaded.model.contacts();
    assert_eq!(contacts.len(), 1);
    assert_eq!(loaded.model.frames()[contacts[0].frame].name, "tip");
    assert_eq!(
        (contacts[0].kind, contacts[0].reference),
        (ContactKind::Point, ReferenceFrame::Local)
    );
    let two = "contacts:\n  - { frame: b, kind: point, reference: local_world_aligned }\n";
    let loaded = load(&arm(two)).unwrap();
    assert_eq!(
        loaded.model.contacts()[0].reference,
        ReferenceFrame::LocalWorldAligned
    );
    // A loop on the planar arm: three rows, one of them zero, two degrees of freedom left.
    let held = load(&arm("contacts:\n  - { frame: tip, to: b, kind: point }\n")).unwrap();
    let [contact] = held.model.contacts() else {
        panic!("one contact")
    };
    let name = |k: usize| held.model.frames()[k].name.as_str();
    assert_eq!((name(contact.frame), contact.to.map(name)), ("tip", Some("b")));
    assert_eq!(free_degrees(&held.model), 2);
    // A frame held whole: six rows, three redundant, one degree of freedom left (counting
    // rows would refuse it).
    let whole = load(&arm("contacts:\n  - { frame: c, kind: frame }\n")).unwrap();
    assert_eq!(free_degrees(&whole.model), 1);
}

#[test]
fn each_mistake_is_one_error_at_its_place() {
    // Line 16 is the first contact (and the list, where what the set holds together is
    // reported), 17 the second (after `contacts:` on line 15).
    let cases = [
        (
            "contacts:\n  - { frame: toe, kind: point }\n",
            &["arm.yaml:16:", "no frame named 'toe'", "tip, b, c"][..],
        ),
        (
            "contacts:\n  - { frame: tip, kind: foot }\n",
            &["arm.yaml:16:", "contact kind `foot`: expected `point` or `frame`"],
        ),
        (
            "contacts:\n  - { frame: tip, kind: point, reference: world }\n",
            &["arm.yaml:16:", "expected `local` or `local_world_aligned`"],
        ),
        (
            "contacts:\n  - { frame: tip, kind: point }\n  - { frame: tip, kind: point }\n",
            &["arm.yaml:17:", "frame 'tip' is held by an earlier contact"],
        ),
        (
            // The arm is planar: the frame's six rows hold three of its four degrees of
            // freedom, the point at `c` two more of which one is new.
            "contacts:\n  - { frame: tip, kind: frame }\n  - { frame: c, kind: point }\n",
            &[
                "arm.yaml:16:",
                "9 rows hold every one of the robot's 4 degrees of freedom",
            ],
        ),
        (
            "contacts:\n  - { frame: tip, to: toe, kind: point }\n",
            &["arm.yaml:16:", "no frame named 'toe' to hold to"],
        ),
        (
            "contacts:\n  - { frame: tip, to: tip, kind: point }\n",
            &["arm.yaml:16:", "frames of one body"],
        ),
        (
            "contacts:\n  - { frame: tip, kind: point, stiffness: 3.0 }\n",
            &["arm.yaml:16:", "stiffness"],
        ),
    ];
    for (contacts, expected) in cases {
        let message = load(&arm(contacts)).expect_err(contacts);
        assert_eq!(message.lines().count(), 1, "{message}");
        for part in expected {
            assert!(message.contains(part), "{message:?} should contain {part:?}");
        }
    }
}

#[test]
fn the_builder_adds_contacts_and_refuses_them_chosen_twice() {
    let chosen = Builder::new("arm.yaml")
        .contact(ContactSpec::new("tip", ContactKind::Point))
        .chosen()
        .clone();
    assert_eq!(chosen.contacts, [ContactSpec::new("tip", ContactKind::Point)]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("arm.yaml");
    std::fs::write(&file, arm("contacts:\n  - { frame: b, kind: point }\n")).unwrap();
    let error = description::load_with(&file, &chosen).unwrap_err().to_string();
    assert!(error.contains("`contacts` was chosen twice"), "{error}");
}
