//! Every way a description can be wrong gives one line that names the file, the place and the
//! problem; suspicious but legal values give warnings.
//!
//! Data-driven: a valid base robot (YAML and URDF), one small edit per case, and the
//! substrings the message must contain. Places are line:column in both formats, and URDF
//! messages also name the element (`joint 'j1'`).

use dyngen_codegen::description::{self, Choices, DescriptionError, Loaded, Location};
use std::path::{Path, PathBuf};

/// The base YAML robot; comments give the line numbers the cases rely on.
const BASE_YAML: &str = "\
name: r
links:
  - name: base
  - name: l1
    inertial:
      mass: 1.0
      inertia: { ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }
joints:
  - name: j1
    type: revolute
    parent: base
    child: l1
    axis: [0, 0, 1]
    limit: { lower: -1.0, upper: 1.0, velocity: 1.0, effort: 1.0 }
";
// line 4: `  - name: l1` (links[1] at 4:5)     line 6: mass value at 6:13
// line 7: inertia value at 7:16               line 9: joints[0] at 9:5
// line 10: type value at 10:11                line 11: parent value at 11:13
// line 12: child value at 12:12               line 13: axis value at 13:11
// line 14: limit value at 14:12

const BASE_URDF: &str = r#"<robot name="r">
  <link name="base"/>
  <link name="l1">
    <inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"#;
// line 3: <link name="l1"> at 3:3; <mass> at 4:15; <inertia> at 4:32
// line 6: <joint name="j1"> at 6:3, its type attribute at 6:20
// line 7: <parent> at 7:5, <child> at 7:26, <axis> at 7:44;  line 8: <limit> at 8:5

/// Where a case's text comes from.
// Test cases, built once each: the size of `Choices` does not matter.
#[allow(clippy::large_enum_variant)]
enum Src {
    /// BASE_YAML with (from, to) replacements, then `extra` appended.
    Yaml(&'static [(&'static str, &'static str)], &'static str),
    /// BASE_URDF with replacements.
    Urdf(&'static [(&'static str, &'static str)], Choices),
    /// A complete YAML text, for the wrapper form (`file` decides where `urdf:` resolves).
    YamlAt(&'static str, PathBuf),
}

fn edit(base: &str, edits: &[(&str, &str)]) -> String {
    let mut text = base.to_owned();
    for (from, to) in edits {
        assert!(text.contains(from), "test bug: {from:?} is not in the base text");
        text = text.replacen(from, to, 1);
    }
    text
}

fn run(src: Src) -> (Result<Loaded, DescriptionError>, String) {
    match src {
        Src::Yaml(edits, extra) => {
            let text = edit(BASE_YAML, edits) + extra;
            (
                description::load_yaml_str(&text, Path::new("bad.yaml")),
                "bad.yaml".into(),
            )
        }
        Src::Urdf(edits, options) => {
            let text = edit(BASE_URDF, edits);
            (
                description::load_urdf_str(&text, Path::new("bad.urdf"), &options),
                "bad.urdf".into(),
            )
        }
        Src::YamlAt(text, file) => {
            let name = file.display().to_string();
            (description::load_yaml_str(text, &file), name)
        }
    }
}

/// The description must be rejected with a message that starts with the file name and
/// contains every expected piece.
fn check(src: Src, expected: &[&str]) {
    let (result, file) = run(src);
    let e = match result {
        Ok(_) => panic!("accepted, expected an error containing {expected:?}"),
        Err(e) => e,
    };
    let msg = e.to_string();
    assert!(
        msg.starts_with(&file),
        "message does not start with the file '{file}': {msg}"
    );
    assert!(!msg.contains('\n'), "message is not one line: {msg}");
    for piece in expected {
        assert!(msg.contains(piece), "message lacks {piece:?}: {msg}");
    }
}

/// The description must load, with one warning containing every expected piece.
fn check_warning(src: Src, expected: &[&str]) {
    let (result, file) = run(src);
    let loaded = result.unwrap_or_else(|e| panic!("rejected: {e}"));
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.starts_with(&file) && expected.iter().all(|p| w.contains(p))),
        "no warning with {expected:?} in {:?}",
        loaded.warnings
    );
}

fn robots(file: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("robots")
        .join(file)
}

fn no_options() -> Choices {
    Choices::default()
}

#[test]
fn base_robots_are_valid() {
    let (yaml, _) = run(Src::Yaml(&[], ""));
    let (urdf, _) = run(Src::Urdf(&[], no_options()));
    let (yaml, urdf) = (yaml.unwrap(), urdf.unwrap());
    assert_eq!(yaml.model, urdf.model);
    assert!(yaml.warnings.is_empty() && urdf.warnings.is_empty());
}

#[test]
fn error_keeps_its_parts() {
    let (result, _) = run(Src::Yaml(&[("axis: [0, 0, 1]", "axis: [0, 0, 0]")], ""));
    let e = result.unwrap_err();
    assert_eq!(e.file, Path::new("bad.yaml"));
    assert_eq!(e.location, Some(Location { line: 13, column: 11 }));
    assert_eq!(e.item.as_deref(), Some("joint 'j1'"));
    assert_eq!(e.message, "axis [0, 0, 0] has zero length");
    assert_eq!(
        e.to_string(),
        "bad.yaml:13:11: joint 'j1': axis [0, 0, 0] has zero length"
    );
}

// ---- syntax and schema -------------------------------------------------------------------

#[test]
fn yaml_syntax_error() {
    check(
        Src::Yaml(&[("effort: 1.0 }", "effort: 1.0")], ""),
        &["bad.yaml:15:1", "did not find expected"],
    );
}

#[test]
fn yaml_unknown_field() {
    check(
        Src::Yaml(&[("axis: [0, 0, 1]", "axes: [0, 0, 1]")], ""),
        &["bad.yaml:13:5", "unknown field `axes`"],
    );
    check(
        Src::Yaml(&[("name: r\n", "name: r\ngravty: [0, 0, -9.81]\n")], ""),
        &[
            "bad.yaml:2:1",
            "unknown field `gravty`, expected one of `name`, `urdf`",
            "`functions`",
        ],
    );
}

/// A choice whose value does not parse is an error at the value (the choices are one
/// flattened struct, whose values serde reads without their places: they are read again).
#[test]
fn yaml_bad_choice_values_have_their_places() {
    check(
        Src::Yaml(&[("name: r\n", "name: r\ngravity: [0, -9.81]\n")], ""),
        &["bad.yaml:2:10: gravity: invalid length 2, expected an array of length 3"],
    );
    check(
        Src::Yaml(&[("name: r\n", "name: r\n\nfloating_base: 1\n")], ""),
        &["bad.yaml:3:16: floating_base: invalid type: integer `1`, expected a boolean"],
    );
    check(
        Src::Yaml(
            &[("name: r\n", "name: r\nlocked_joints: { j1: 0.1, j1: 0.2 }\n")],
            "",
        ),
        &["bad.yaml:2:", "joint 'j1' is locked twice"],
    );
    // A robot file that is not a map says what it expected.
    check(
        Src::YamlAt("- a\n", "w.yaml".into()),
        &["w.yaml:1:1", "expected struct RobotFile"],
    );
}

#[test]
fn yaml_missing_name() {
    check(
        Src::Yaml(&[("  - name: base\n", "  - {}\n")], ""),
        &["bad.yaml:3:5", "missing field `name`"],
    );
    check(
        Src::Yaml(&[("name: r\n", "")], ""),
        &["bad.yaml:1:1", "`name:` is required"],
    );
}

#[test]
fn yaml_neither_or_both_forms() {
    check(
        Src::YamlAt("name: r\n", "w.yaml".into()),
        &["w.yaml:1:1", "give either `urdf:`"],
    );
    check(
        Src::Yaml(&[("name: r\n", "name: r\nurdf: r.urdf\n")], ""),
        &["bad.yaml:4:3", "`urdf:` and `links:` cannot be used together"],
    );
}

#[test]
fn yaml_wrapper_with_missing_urdf_names_both_files() {
    let file = Path::new("some/dir/wrapper.yaml");
    check(
        Src::YamlAt("urdf: urdf/missing.urdf\n", file.into()),
        &[
            "wrapper.yaml:1:7",
            "cannot read URDF file",
            &Path::new("some/dir")
                .join("urdf/missing.urdf")
                .display()
                .to_string(),
        ],
    );
}

#[test]
fn xml_syntax_error() {
    check(
        Src::Urdf(&[("<child link=\"l1\"/>", "<child link=\"l1\">")], no_options()),
        &["bad.urdf:9:3", "XML syntax error", "expected 'child' tag"],
    );
}

#[test]
fn urdf_malformed_number() {
    check(
        Src::Urdf(&[("<mass value=\"1\"/>", "<mass value=\"1 kg\"/>")], no_options()),
        &["bad.urdf:4:21", "link 'l1'", "value=\"1 kg\" is not a number"],
    );
}

#[test]
fn urdf_missing_names_and_elements() {
    check(
        Src::Urdf(&[("<link name=\"l1\">", "<link>")], no_options()),
        &["bad.urdf:3:3", "<link> has no `name`"],
    );
    check(
        Src::Urdf(
            &[(
                "<joint name=\"j1\" type=\"revolute\">",
                "<joint type=\"revolute\">",
            )],
            no_options(),
        ),
        &["bad.urdf:6:3", "<joint> has no `name`"],
    );
    check(
        Src::Urdf(&[("<parent link=\"base\"/>", "")], no_options()),
        &["bad.urdf:6:3", "joint 'j1'", "no <parent>"],
    );
    check(
        Src::Urdf(&[("<mass value=\"1\"/>", "")], no_options()),
        &["bad.urdf:4:5", "link 'l1'", "no <mass>"],
    );
    check(
        Src::Urdf(&[("ixx=\"0.1\" ", "")], no_options()),
        &["bad.urdf:4:", "link 'l1'", "no `ixx`"],
    );
    check(
        Src::Urdf(&[("effort=\"1\" ", "")], no_options()),
        &["bad.urdf:8:5", "joint 'j1'", "<limit> has no `effort`"],
    );
}

#[test]
fn revolute_joint_without_limit() {
    check(
        Src::Urdf(
            &[(
                "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>",
                "",
            )],
            no_options(),
        ),
        &["bad.urdf:6:3", "joint 'j1'", "needs a limit"],
    );
    check(
        Src::Yaml(
            &[(
                "    limit: { lower: -1.0, upper: 1.0, velocity: 1.0, effort: 1.0 }\n",
                "",
            )],
            "",
        ),
        &["bad.yaml:9:5", "joint 'j1'", "needs a limit"],
    );
}

#[test]
fn xacro_file() {
    check(
        Src::Urdf(&[("<robot name=\"r\">", "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><xacro:include filename=\"a.xacro\"/>")], no_options()),
        &["bad.urdf:1:", "xacro"],
    );
}

// ---- joint types --------------------------------------------------------------------------

#[test]
fn unknown_joint_type() {
    check(
        Src::Yaml(&[("type: revolute", "type: hinge")], ""),
        &["bad.yaml:10:11", "joint 'j1'", "unknown joint type 'hinge'"],
    );
    check(
        Src::Urdf(&[("type=\"revolute\"", "type=\"hinge\"")], no_options()),
        &["bad.urdf:6:20", "joint 'j1'", "unknown joint type 'hinge'"],
    );
}

#[test]
fn floating_and_planar_joints() {
    for kind in ["floating", "planar"] {
        let msg = match kind {
            "floating" => "type 'floating' is not supported inside the tree; a robot whose root link moves \
                           freely is loaded with `floating_base: true`"
                .to_owned(),
            _ => format!("type '{kind}' is not supported"),
        };
        let edits: &'static [(&str, &str)] = match kind {
            "floating" => &[("type=\"revolute\"", "type=\"floating\"")],
            _ => &[("type=\"revolute\"", "type=\"planar\"")],
        };
        check(
            Src::Urdf(edits, no_options()),
            &["bad.urdf:6:20", "joint 'j1'", &msg],
        );
    }
    check(
        Src::Yaml(&[("type: revolute", "type: floating")], ""),
        &["bad.yaml:10:11", "joint 'j1'", "not supported"],
    );
}

// ---- names and tree shape -----------------------------------------------------------------

#[test]
fn duplicate_names() {
    check(
        Src::Yaml(&[("  - name: l1\n", "  - name: base\n")], ""),
        &[
            "bad.yaml:4:5",
            "link 'base'",
            "duplicate link name (first defined at 3:5)",
        ],
    );
    check(
        Src::Yaml(&[], "  - { name: j1, type: fixed, parent: l1, child: base }\n"),
        &["bad.yaml:15:5", "joint 'j1'", "duplicate joint name"],
    );
    check(
        Src::Urdf(&[("<link name=\"l1\">", "<link name=\"base\">")], no_options()),
        &["bad.urdf:3:3", "link 'base'", "duplicate link name"],
    );
}

#[test]
fn dangling_link_names() {
    check(
        Src::Yaml(&[("parent: base", "parent: link9")], ""),
        &[
            "bad.yaml:11:13",
            "joint 'j1'",
            "parent link 'link9' is not defined",
        ],
    );
    check(
        Src::Yaml(&[("child: l1", "child: link9")], ""),
        &[
            "bad.yaml:12:12",
            "joint 'j1'",
            "child link 'link9' is not defined",
        ],
    );
    check(
        Src::Urdf(
            &[("<parent link=\"base\"/>", "<parent link=\"link9\"/>")],
            no_options(),
        ),
        &["bad.urdf:7:5", "joint 'j1'", "parent link 'link9' is not defined"],
    );
}

#[test]
fn cycles() {
    check(
        Src::Yaml(&[("  - name: base\n", "  - name: base\n  - name: l2\n")], "  - { name: j2, type: fixed, parent: l1, child: l2 }\n  - { name: j3, type: fixed, parent: l2, child: l1 }\n"),
        &["bad.yaml:17:49", "joint 'j3'", "link 'l1' already hangs from joint 'j1'"],
    );
    // a true loop, not reachable from the base
    check(
        Src::Yaml(
            &[("  - name: base\n", "  - name: base\n  - name: a\n  - name: b\n")],
            "  - { name: ja, type: fixed, parent: a, child: b }\n  - { name: jb, type: fixed, parent: b, child: a }\n",
        ),
        &["bad.yaml:17:5", "joint 'ja'", "joints 'ja' → 'jb' form a cycle"],
    );
    check(
        Src::Yaml(&[("child: l1", "child: base")], ""),
        &["bad.yaml:9:5", "joint 'j1'", "parent and child are the same link"],
    );
}

#[test]
fn several_roots_and_disconnected_links() {
    check(
        Src::Yaml(
            &[(
                "  - name: base\n",
                "  - name: base\n  - name: base2\n  - name: m\n",
            )],
            "  - { name: j2, type: fixed, parent: base2, child: m }\n",
        ),
        &[
            "bad.yaml:4:5",
            "link 'base2'",
            "several root links",
            "'base', 'base2'",
        ],
    );
    check(
        Src::Yaml(&[("  - name: base\n", "  - name: base\n  - name: lonely\n")], ""),
        &["bad.yaml:4:5", "link 'lonely'", "not connected to any joint"],
    );
    check(
        Src::Urdf(
            &[(
                "<link name=\"base\"/>",
                "<link name=\"base\"/><link name=\"lonely\"/>",
            )],
            no_options(),
        ),
        &["bad.urdf:2:22", "link 'lonely'", "not connected"],
    );
}

#[test]
fn no_moving_joint() {
    check(
        Src::Yaml(&[("type: revolute", "type: fixed")], ""),
        &["bad.yaml", "no moving joints"],
    );
}

// ---- numbers ------------------------------------------------------------------------------

#[test]
fn nan_and_infinity_are_rejected() {
    check(
        Src::Yaml(&[("axis: [0, 0, 1]", "axis: [0, .nan, 1]")], ""),
        &["bad.yaml:13:11", "joint 'j1'", "axis [0, NaN, 1] is not finite"],
    );
    check(
        Src::Yaml(&[("mass: 1.0", "mass: .inf")], ""),
        &["bad.yaml:6:13", "link 'l1'", "mass inf is not finite"],
    );
    check(
        Src::Yaml(&[("ixy: 0.0", "ixy: -.inf")], ""),
        &["bad.yaml:7:16", "link 'l1'", "not finite"],
    );
    check(
        Src::Yaml(&[("upper: 1.0", "upper: .NaN")], ""),
        &["bad.yaml:14:12", "joint 'j1'", "limit", "not finite"],
    );
    check(
        Src::Yaml(
            &[("    axis:", "    origin: { xyz: [0, 0, .inf] }\n    axis:")],
            "",
        ),
        &[
            "bad.yaml:13:13",
            "joint 'j1'",
            "origin xyz [0, 0, inf] is not finite",
        ],
    );
    check(
        Src::Yaml(&[("name: r\n", "name: r\ngravity: [0, 0, .nan]\n")], ""),
        &["bad.yaml:2:10", "gravity [0, 0, NaN] is not finite"],
    );
    check(
        Src::Urdf(
            &[("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 nan 1\"/>")],
            no_options(),
        ),
        &["bad.urdf:7:44", "joint 'j1'", "not finite"],
    );
    check(
        Src::Urdf(&[("iyy=\"0.1\"", "iyy=\"inf\"")], no_options()),
        &["bad.urdf:4:32", "link 'l1'", "not finite"],
    );
}

#[test]
fn negative_mass() {
    check(
        Src::Yaml(&[("mass: 1.0", "mass: -1.0")], ""),
        &["bad.yaml:6:13", "link 'l1'", "negative mass -1"],
    );
    check(
        Src::Urdf(&[("<mass value=\"1\"/>", "<mass value=\"-2\"/>")], no_options()),
        &["bad.urdf:4:15", "link 'l1'", "negative mass -2"],
    );
}

/// A negative principal moment far beyond rounding (the triangle excess it makes is above half
/// the largest moment) is refused by default, with the repair named.
#[test]
fn inertia_with_a_gross_negative_moment() {
    check(
        Src::Yaml(&[("ixy: 0.0", "ixy: 0.2")], ""),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "inertia is not physical: principal moment -0.1 kg·m² is negative",
            "which breaks the triangle inequality by 100%",
            "`inertia: repair`",
        ],
    );
    check(
        Src::Urdf(&[("ixx=\"0.1\"", "ixx=\"-0.1\"")], no_options()),
        &[
            "bad.urdf:4:32",
            "link 'l1'",
            "principal moment -0.1 kg·m² is negative",
        ],
    );
}

#[test]
fn inertia_grossly_violating_the_triangle_inequality() {
    check(
        Src::Yaml(&[("izz: 0.1", "izz: 0.5")], ""),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "triangle inequality broken by 60%: I1 + I2 = 0.2 < I3 = 0.5 kg·m², more than the 50% loaded as written",
        ],
    );
}

/// `inertia: strict` refuses what the default loads with a warning: slight defects of each
/// kind (the warnings themselves: `codegen/tests/suite/non_physical_inertia.rs`).
#[test]
fn strict_inertia_refuses_slight_defects() {
    let strict = || Choices {
        inertia: description::NonPhysicalInertia::Strict,
        ..Choices::default()
    };
    check(
        Src::Urdf(&[("ixx=\"0.1\"", "ixx=\"-0.001\"")], strict()),
        &[
            "bad.urdf:4:32",
            "link 'l1'",
            "principal moment -0.001 kg·m² is negative",
            "`inertia: strict` refuses it",
        ],
    );
    check(
        Src::Yaml(&[("izz: 0.1", "izz: 0.3")], "inertia: strict\n"),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "triangle inequality broken by 33%",
            "`inertia: strict` refuses it",
        ],
    );
    // a thin rod along z: on the triangle boundary, but mass without extent about its axis
    check(
        Src::Yaml(&[("izz: 0.1", "izz: 0.0")], "inertia: strict\n"),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "inertia is singular: mass 1 kg with a principal moment of 0",
            "`inertia: strict` refuses it",
        ],
    );
}

#[test]
fn zero_length_axis() {
    check(
        Src::Yaml(&[("axis: [0, 0, 1]", "axis: [0, 0, 0]")], ""),
        &["bad.yaml:13:11", "joint 'j1'", "axis [0, 0, 0] has zero length"],
    );
    check(
        Src::Urdf(
            &[("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 0\"/>")],
            no_options(),
        ),
        &["bad.urdf:7:44", "joint 'j1'", "zero length"],
    );
}

#[test]
fn lower_limit_above_upper() {
    check(
        Src::Yaml(&[("lower: -1.0", "lower: 2.0")], ""),
        &[
            "bad.yaml:14:12",
            "joint 'j1'",
            "lower limit 2 is greater than upper limit 1",
        ],
    );
    check(
        Src::Urdf(&[("lower=\"-1\"", "lower=\"3\"")], no_options()),
        &[
            "bad.urdf:8:5",
            "joint 'j1'",
            "lower limit 3 is greater than upper limit 1",
        ],
    );
}

// ---- user choices: end-effector, locked joints, mimic ---------------------------------------

#[test]
fn unknown_end_effector() {
    check(
        Src::Yaml(&[("name: r\n", "name: r\nend_effector: tool9\n")], ""),
        &[
            "bad.yaml:2:15",
            "end-effector 'tool9'",
            "link 'tool9' is not defined",
        ],
    );
    let options = Choices {
        end_effector: Some(description::FrameSpec::link("tool9")),
        ..no_options()
    };
    check(
        Src::Urdf(&[], options),
        &["bad.urdf", "end-effector 'tool9'", "not defined"],
    );
    check(
        Src::Yaml(
            &[(
                "name: r\n",
                "name: r\nend_effector: { link: l1, offset: [0, 0, 1] }\n",
            )],
            "",
        ),
        &["bad.yaml:2:", "unknown field `offset`"],
    );
}

#[test]
fn end_effector_on_the_base() {
    check(
        Src::Yaml(&[("name: r\n", "name: r\nend_effector: base\n")], ""),
        &[
            "bad.yaml:2:15",
            "end-effector 'base'",
            "does not move with any joint",
        ],
    );
}

#[test]
fn unknown_locked_joint() {
    check(
        Src::Yaml(&[("name: r\n", "name: r\nlocked_joints: { j9: 0.0 }\n")], ""),
        &["bad.yaml:2:22", "locked joint 'j9'", "unknown locked joint"],
    );
    let options = Choices {
        locked_joints: vec![("j9".into(), 0.0)],
        ..no_options()
    };
    check(
        Src::Urdf(&[], options),
        &["bad.urdf", "locked joint 'j9'", "unknown locked joint"],
    );
}

#[test]
fn locked_joint_outside_its_limits() {
    let yaml =
        "urdf: urdf/panda.urdf\nlocked_joints: { panda_finger_joint1: 0.05, panda_finger_joint2: 0.0 }\n";
    check(
        Src::YamlAt(yaml, robots("bad_panda.yaml")),
        &[
            "bad_panda.yaml:2:39",
            "locked joint 'panda_finger_joint1'",
            "position 0.05 is outside the joint limits [0, 0.04]",
        ],
    );
}

#[test]
fn locked_joint_twice_or_fixed() {
    check(
        Src::Yaml(
            &[("name: r\n", "name: r\nlocked_joints: { j1: 0.0, j1: 0.1 }\n")],
            "",
        ),
        &["bad.yaml:2:", "joint 'j1' is locked twice"],
    );
    check(
        Src::Yaml(
            &[
                ("name: r\n", "name: r\nlocked_joints: { j2: 0.0 }\n"),
                ("  - name: base\n", "  - name: base\n  - name: t\n"),
            ],
            "  - { name: j2, type: fixed, parent: l1, child: t }\n",
        ),
        &[
            "bad.yaml:2:22",
            "locked joint 'j2'",
            "only moving joints can be locked",
        ],
    );
}

/// A mimic joint follows its master: chains of mimic joints are resolved to the joint at their
/// end, multipliers and offsets composed.
#[test]
fn unlocked_mimic_joints_follow_their_master() {
    let (loaded, _) = run(Src::Yaml(
        &[
            ("name: r\n", "name: r\nend_effector: l1\n"),
            ("  - name: base\n", "  - name: base\n  - name: t\n  - name: u\n"),
        ],
        "  - { name: j2, type: continuous, parent: l1, child: t, mimic: { joint: j3, multiplier: 2.0, offset: 0.1 } }\n\
         \x20 - { name: j3, type: continuous, parent: l1, child: u, mimic: { joint: j1, multiplier: -0.5, offset: 0.3 } }\n",
    ));
    let model = loaded.unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!((model.dof(), model.joints().len()), (1, 3));
    let names: Vec<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
    let j2 = names.iter().position(|n| *n == "j2").unwrap();
    let m = model.mimics()[j2].expect("j2 is a mimic joint");
    assert_eq!(names[m.master], "j1");
    // q2 = 2 (−0.5 q1 + 0.3) + 0.1
    assert_eq!((m.multiplier, m.offset), (-1.0, 2.0 * 0.3 + 0.1));
}

#[test]
fn mimic_of_itself_or_in_a_cycle() {
    let two = |j2: &'static str| Src::Yaml(&[("  - name: base\n", "  - name: base\n  - name: t\n")], j2);
    check(
        two("  - { name: j2, type: continuous, parent: l1, child: t, mimic: { joint: j2 } }\n"),
        &["bad.yaml:16:64", "joint 'j2'", "mimics itself"],
    );
    check(
        Src::Urdf(
            &[("<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>", "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/><mimic joint=\"j2\"/>"), ("</robot>", "<link name=\"t\"/><joint name=\"j2\" type=\"continuous\"><parent link=\"l1\"/><child link=\"t\"/><mimic joint=\"j1\"/></joint></robot>")],
            no_options(),
        ),
        &["bad.urdf:8:", "joint 'j1'", "mimic joints 'j1' → 'j2' → 'j1' form a cycle"],
    );
}

#[test]
fn mimic_of_a_fixed_or_locked_joint() {
    check(
        Src::Yaml(
            &[("  - name: base\n", "  - name: base\n  - name: t\n  - name: u\n")],
            "  - { name: jf, type: fixed, parent: l1, child: t }\n  - { name: j2, type: continuous, parent: l1, child: u, mimic: { joint: jf } }\n",
        ),
        &["bad.yaml:18:64", "joint 'j2'", "mimics joint 'jf', which is fixed"],
    );
    check(
        Src::Yaml(
            &[
                ("name: r\n", "name: r\nlocked_joints: { j1: 0.5 }\n"),
                ("  - name: base\n", "  - name: base\n  - name: t\n"),
            ],
            "  - { name: j2, type: continuous, parent: l1, child: t, mimic: { joint: j1, multiplier: 2.0, offset: 0.1 } }\n",
        ),
        &["bad.yaml:17:64", "joint 'j2'", "mimics joint 'j1', which is locked at 0.5: lock 'j2' too, at 1.1"],
    );
}

#[test]
fn mimic_with_zero_multiplier_or_joint_parameters() {
    let mimic = |m: &'static str| Src::Yaml(&[("  - name: base\n", "  - name: base\n  - name: t\n")], m);
    check(
        mimic("  - { name: j2, type: continuous, parent: l1, child: t, mimic: { joint: j1, multiplier: 0.0 } }\n"),
        &["bad.yaml:16:64", "joint 'j2'", "with multiplier 0: the joint would never move"],
    );
    check(
        Src::Yaml(
            &[
                ("name: r\n", "name: r\njoint_parameters: { columns: [armature] }\n"),
                ("  - name: base\n", "  - name: base\n  - name: t\n"),
            ],
            "  - { name: j2, type: continuous, parent: l1, child: t, mimic: { joint: j1 } }\n",
        ),
        &["bad.yaml:2:", "joint-level parameters (armature, friction, offset) are not supported on a robot with mimic joints"],
    );
}

#[test]
fn unknown_file_type() {
    let e = description::load(Path::new("robot.txt")).unwrap_err().to_string();
    assert!(e.starts_with("robot.txt: unknown file type"), "{e}");
    let e = description::load(Path::new("no/such/robot.yaml"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("no/such/robot.yaml: cannot read file"), "{e}");
}

// ---- warnings -----------------------------------------------------------------------------

#[test]
fn massless_leaf_warns() {
    check_warning(
        Src::Yaml(
            &[
                ("mass: 1.0", "mass: 0.0"),
                (
                    "ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1",
                    "ixx: 0, ixy: 0, ixz: 0, iyy: 0, iyz: 0, izz: 0",
                ),
            ],
            "",
        ),
        &["bad.yaml:4:5", "link 'l1'", "zero mass and no children"],
    );
    check_warning(Src::Urdf(&[("<inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial>", "")], no_options()), &["bad.urdf:3:3", "link 'l1'", "zero mass and no children"]);
}

/// A `<mimic>` on a fixed joint (xacro macros write them) loads, with a warning.
#[test]
fn mimic_on_a_fixed_joint_warns_and_loads() {
    check_warning(
        Src::Urdf(
            &[(
                "</robot>",
                "  <link name=\"pad\"/>\n  <joint name=\"pad_joint\" type=\"fixed\"><parent link=\"l1\"/><child link=\"pad\"/><mimic joint=\"j1\"/></joint>\n</robot>",
            )],
            no_options(),
        ),
        &["bad.urdf:11:", "joint 'pad_joint'", "<mimic> of 'j1' on a fixed joint is ignored"],
    );
}

#[test]
fn a_xacro_file_says_to_expand_it() {
    let e = description::load(Path::new("arm.urdf.xacro"))
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "arm.urdf.xacro: a xacro file: expand it first (`xacro robot.urdf.xacro > robot.urdf`) and load the URDF"
    );
}

#[test]
fn massless_body_with_children_warns() {
    check_warning(
        Src::Yaml(
            &[
                ("  - name: base\n", "  - name: base\n  - name: hub\n"),
                ("child: l1", "child: hub"),
            ],
            "  - { name: j2, type: continuous, parent: hub, child: l1, axis: [1, 0, 0] }\n",
        ),
        &["bad.yaml:4:5", "link 'hub'", "zero total mass"],
    );
}

#[test]
fn point_mass_warns() {
    check_warning(
        Src::Yaml(
            &[(
                "ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1",
                "ixx: 0, ixy: 0, ixz: 0, iyy: 0, iyz: 0, izz: 0",
            )],
            "",
        ),
        &["bad.yaml:7:16", "link 'l1'", "point mass"],
    );
}

/// Slightly non-physical inertias load as written, one warning each (default `inertia: as_written`).
#[test]
fn slightly_non_physical_inertia_warns() {
    check_warning(
        Src::Yaml(&[("izz: 0.1", "izz: 0.3")], ""),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "triangle inequality broken by 33%",
            "loaded as written",
        ],
    );
    check_warning(
        Src::Urdf(&[("ixx=\"0.1\"", "ixx=\"-0.001\"")], no_options()),
        &[
            "bad.urdf:4:32",
            "link 'l1'",
            "principal moment -0.001 kg·m² is negative",
            "`inertia: repair`",
        ],
    );
    check_warning(
        Src::Yaml(&[("izz: 0.1", "izz: 0.0")], ""),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "inertia is singular",
            "no extent about one axis",
        ],
    );
}

#[test]
fn inertia_without_mass_warns() {
    check_warning(
        Src::Yaml(&[("mass: 1.0", "mass: 0.0")], ""),
        &["bad.yaml:7:16", "link 'l1'", "zero mass but a non-zero inertia"],
    );
}

#[test]
fn immovable_joint_warns() {
    check_warning(
        Src::Yaml(&[("lower: -1.0, upper: 1.0", "lower: 0.5, upper: 0.5")], ""),
        &["bad.yaml:14:12", "joint 'j1'", "both 0.5", "cannot move"],
    );
    check_warning(
        Src::Urdf(
            &[("lower=\"-1\" upper=\"1\"", "lower=\"0\" upper=\"0\"")],
            no_options(),
        ),
        &["bad.urdf:8:5", "joint 'j1'", "both 0", "cannot move"],
    );
}

#[test]
fn zero_velocity_or_effort_limit_warns() {
    check_warning(
        Src::Yaml(&[("velocity: 1.0", "velocity: 0.0")], ""),
        &["bad.yaml:14:12", "joint 'j1'", "velocity limit is 0"],
    );
    check_warning(
        Src::Urdf(&[("effort=\"1\"", "effort=\"0\"")], no_options()),
        &["bad.urdf:8:5", "joint 'j1'", "effort limit is 0"],
    );
}

#[test]
fn huge_mass_warns() {
    // Scaled inertia too, so that only the mass warning can match.
    check_warning(
        Src::Yaml(
            &[
                ("mass: 1.0", "mass: 20000.0"),
                (
                    "ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1",
                    "ixx: 2000, ixy: 0, ixz: 0, iyy: 2000, iyz: 0, izz: 2000",
                ),
            ],
            "",
        ),
        &["bad.yaml:6:13", "link 'l1'", "mass 20000 kg", "grams"],
    );
}

#[test]
fn far_origins_warn() {
    check_warning(
        Src::Yaml(
            &[(
                "axis: [0, 0, 1]",
                "axis: [0, 0, 1]\n    origin: { xyz: [0, 0, 150] }",
            )],
            "",
        ),
        &[
            "bad.yaml:14:13",
            "joint 'j1'",
            "origin [0, 0, 150]",
            "millimetres",
        ],
    );
    check_warning(
        Src::Urdf(
            &[("<inertial>", "<inertial><origin xyz=\"0 -250 0\"/>")],
            no_options(),
        ),
        &[
            "bad.urdf:4",
            "link 'l1'",
            "centre of mass [0, -250, 0]",
            "millimetres",
        ],
    );
}

#[test]
fn inertia_that_does_not_fit_the_mass_warns() {
    // Inertia in g·mm² with mass in kg: radius of gyration far below a millimetre ...
    check_warning(
        Src::Yaml(
            &[(
                "ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1",
                "ixx: 1e-9, ixy: 0, ixz: 0, iyy: 1e-9, iyz: 0, izz: 1e-9",
            )],
            "",
        ),
        &[
            "bad.yaml:7:16",
            "link 'l1'",
            "radius of gyration",
            "check the units",
        ],
    );
    // ... and mass in grams with inertia in kg·m²: far above ten metres.
    check_warning(
        Src::Urdf(
            &[
                ("<mass value=\"1\"/>", "<mass value=\"0.0001\"/>"),
                (
                    "ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"",
                    "ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"",
                ),
            ],
            no_options(),
        ),
        &["bad.urdf:4", "link 'l1'", "radius of gyration √(I/m) = 100 m"],
    );
}

#[test]
fn plausible_values_do_not_warn() {
    // The base robots (1 kg, 0.1 kg·m²: radius of gyration 0.32 m) and every committed robot.
    let (yaml, _) = run(Src::Yaml(&[], ""));
    assert_eq!(yaml.unwrap().warnings, Vec::<String>::new());
    for robot in ["arm7.yaml", "panda.yaml", "panda_rounded.yaml", "ur5.yaml"] {
        let loaded = description::load(&robots(robot)).unwrap();
        assert_eq!(loaded.warnings, Vec::<String>::new(), "{robot}");
    }
}

// ---- robustness ---------------------------------------------------------------------------

#[test]
fn odd_inputs_give_errors_not_panics() {
    let deep_yaml = "[".repeat(5000) + &"]".repeat(5000);
    let deep_xml = format!(
        "<robot name=\"r\">{}{}</robot>",
        "<a>".repeat(5000),
        "</a>".repeat(5000)
    );
    let huge = BASE_YAML
        .replace("0.1", "1e308")
        .replace("mass: 1.0", "mass: 1e308");
    let yamls: Vec<String> = vec![
        String::new(),
        "---\n".into(),
        "[]\n".into(),
        "name: r\nlinks: 3\n".into(),
        "name: r\nlinks: []\n".into(),
        "name: r\nlinks:\n  - name: a\n".into(),
        "urdf: ''\n".into(),
        "a: &x [*x]\n".into(),
        "name: r\n---\nname: s\n".into(),
        deep_yaml,
        huge,
    ];
    for text in &yamls {
        match description::load_yaml_str(text, Path::new("odd.yaml")) {
            Ok(_) => {}
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.starts_with("odd.yaml") && !msg.contains('\n'), "{msg}");
            }
        }
    }
    let urdfs: Vec<String> = vec![
        String::new(),
        "<robot/>".into(),
        "<robot name=\"r\"/>".into(),
        "<notrobot/>".into(),
        "<robot name=\"r\"><link name=\"a\"/></robot>".into(),
        deep_xml,
        BASE_URDF.replace("0.1", "1e308"),
    ];
    for text in &urdfs {
        match description::load_urdf_str(text, Path::new("odd.urdf"), &Choices::default()) {
            Ok(_) => {}
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.starts_with("odd.urdf") && !msg.contains('\n'), "{msg}");
            }
        }
    }
}

// ---- the examples of TESTING.md -----------------------------------------------------------

/// Every file in `codegen/tests/data/bad/` is rejected, and TESTING.md shows its message exactly
/// as `cargo xtask gen` prints it from the workspace root (`error: ` and the message), so the
/// document cannot go stale.
#[test]
fn testing_md_shows_every_bad_input_message() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let doc = std::fs::read_to_string(root.join("TESTING.md")).expect("TESTING.md");
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("codegen/tests/data/bad"))
        .expect("codegen/tests/data/bad")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    for file in files {
        let name = file.file_name().expect("name").to_string_lossy().into_owned();
        // As the user types it from the workspace root (the tests run in `codegen/`).
        let relative = PathBuf::from("tests/data/bad").join(&name);
        let e = description::load(&relative)
            .err()
            .unwrap_or_else(|| panic!("{name} is accepted"));
        let line = format!("error: codegen/{e}");
        assert!(
            doc.contains(&line),
            "TESTING.md lacks the message of {name}:\n{line}"
        );
    }
}

#[cfg(unix)]
#[test]
fn device_files_are_refused_not_read_forever() {
    let e = description::load(Path::new("/dev/zero.yaml"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/dev/zero.yaml: cannot read file"), "{e}");
    let scratch = dyngen_testkit::scratch::scratch_dir("dev");
    let dir = scratch.path();
    let wrapper = dir.join("wrapper.yaml");
    std::fs::write(&wrapper, "urdf: /dev/zero\n").expect("write");
    let e = description::load(&wrapper).unwrap_err().to_string();
    assert!(
        e.contains("cannot read URDF file '/dev/zero': not a regular file"),
        "{e}"
    );
}
