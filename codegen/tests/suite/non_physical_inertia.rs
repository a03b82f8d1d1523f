//! Links whose inertia no real body can have (`codegen/tests/data/non-physical/`, two-joint
//! arms whose forearm has each defect): loaded as written with one warning per link by
//! default, refused with `inertia: strict`, replaced by the nearest physical inertia with
//! `inertia: repair`; a gross defect refused unless repaired or welded to the base. The
//! dynamics of a model loaded as written are checked against the oracles that use no dynamics
//! algorithm, and exports of such models load back in the default mode. (The Allegro hand, a
//! vendor URDF with such links, against Pinocchio: `example_robot_data.rs`.)

use dyngen_testkit as common;

use common::oracles::{assert_passed, check_all};
use common::random_model::random_state;
use common::workspace_root;
use dyngen_codegen::description::{
    from_urdf_rs, load_urdf_str, load_with, load_yaml_str, to_urdf_rs, Choices, Loaded, NonPhysicalInertia,
};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::{inertia_defect, Inertia, InertiaDefectKind, Model};
use dyngen_codegen::{urdf_rs, Builder};
use nalgebra::{Matrix3, Matrix4, Vector3};
use std::path::{Path, PathBuf};

const DATA: &str = "codegen/tests/data/non-physical";

/// A file of the test data, as the messages name it.
fn data(file: &str) -> PathBuf {
    workspace_root().join(DATA).join(file)
}

fn load(file: &str, inertia: NonPhysicalInertia) -> Result<Loaded, String> {
    let options = Choices {
        inertia,
        ..Choices::default()
    };
    load_with(&data(file), &options).map_err(|e| e.to_string())
}

/// A YAML file with `inertia: <choice>` added (a YAML file states its own choices).
fn load_yaml_with(file: &str, inertia: NonPhysicalInertia) -> Result<Loaded, String> {
    let text = std::fs::read_to_string(data(file)).expect("test data");
    let text = format!("{text}inertia: {}\n", inertia.keyword());
    load_yaml_str(&text, &data(file)).map_err(|e| e.to_string())
}

fn load_any(file: &str, inertia: NonPhysicalInertia) -> Result<Loaded, String> {
    if file.ends_with(".yaml") {
        load_yaml_with(file, inertia)
    } else {
        load(file, inertia)
    }
}

/// One arm per defect kind: the file, the place of the defective inertia, its link, what the
/// message says, and the tensor as written (ixx, ixy, ixz, iyy, iyz, izz).
struct Case {
    file: &'static str,
    place: &'static str,
    link: &'static str,
    says: &'static str,
    kind: InertiaDefectKind,
    written: [f64; 6],
}

const CASES: [Case; 4] = [
    Case {
        file: "negative-moment.urdf",
        place: "negative-moment.urdf:16:7",
        link: "link 'lower'",
        says: "inertia is not physical: principal moment -1e-4 kg·m² is negative (principal moments \
               [-1e-4, 0.01, 0.01] kg·m²)",
        kind: InertiaDefectKind::NegativeMoment,
        written: [-1e-4, 0.0, 0.0, 0.01, 0.0, 0.01],
    },
    Case {
        file: "triangle-inequality.yaml",
        place: "triangle-inequality.yaml:15:16",
        link: "link 'lower'",
        says: "inertia is not physical: triangle inequality broken by 17%: I1 + I2 = 0.02 < I3 = 0.024 \
               kg·m²",
        kind: InertiaDefectKind::TriangleInequality,
        written: [0.01, 0.0, 0.0, 0.01, 0.0, 0.024],
    },
    Case {
        file: "no-extent.urdf",
        place: "no-extent.urdf:16:7",
        link: "link 'lower'",
        says: "inertia is singular: mass 1 kg with a principal moment of 0 kg·m² (the others 0.01 and \
               0.01 kg·m²)",
        kind: InertiaDefectKind::NoExtent,
        written: [0.0, 0.0, 0.0, 0.01, 0.0, 0.01],
    },
    Case {
        file: "gross-on-base.urdf",
        place: "gross-on-base.urdf:15:7",
        link: "link 'antenna'",
        says: "inertia is not physical: principal moment -3.53486e-8 kg·m² is negative",
        kind: InertiaDefectKind::NegativeMoment,
        written: [2.371e-8, 6.119e-8, 1.179e-8, 2.833e-8, 7.74e-9, 3.849e-8],
    },
];

fn tensor([ixx, ixy, ixz, iyy, iyz, izz]: [f64; 6]) -> Matrix3<f64> {
    Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz)
}

fn principal_moments(t: &Matrix3<f64>) -> [f64; 3] {
    let e = t.symmetric_eigenvalues();
    let mut m = [e[0], e[1], e[2]];
    m.sort_by(f64::total_cmp);
    m
}

/// The pseudo-inertia `[[Σ, h], [hᵀ, m]]` of a body about its frame's origin (`Σ = ½ tr(I)·1 − I`):
/// positive semi-definite exactly when the body is a real mass distribution.
fn pseudo_inertia(body: &Inertia) -> Matrix4<f64> {
    let c = body.com;
    let about_origin = body.inertia_com + (Matrix3::identity() * c.dot(&c) - c * c.transpose()) * body.mass;
    let sigma = Matrix3::identity() * (0.5 * about_origin.trace()) - about_origin;
    let h: Vector3<f64> = c * body.mass;
    let mut j = Matrix4::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&sigma);
    j.fixed_view_mut::<3, 1>(0, 3).copy_from(&h);
    j.fixed_view_mut::<1, 3>(3, 0).copy_from(&h.transpose());
    j[(3, 3)] = body.mass;
    j
}

fn body<'m>(model: &'m Model, name: &str) -> &'m Inertia {
    &model
        .bodies()
        .iter()
        .find(|b| b.name == name)
        .unwrap_or_else(|| panic!("no body '{name}'"))
        .inertia
}

#[test]
fn each_defect_loads_as_written_with_one_warning_naming_file_place_and_link() {
    for case in &CASES {
        let loaded = load_any(case.file, NonPhysicalInertia::AsWritten).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded.warnings.len(), 1, "{}: {:#?}", case.file, loaded.warnings);
        let warning = &loaded.warnings[0];
        let start = format!("{}: {}: {}", data(case.place).display(), case.link, case.says);
        assert!(
            warning.starts_with(&start),
            "{warning}\nexpected it to start with\n{start}"
        );
        assert!(!warning.contains('\n'), "{warning}");
        // As written: the link's tensor in the model is the file's, turned into the joint frame.
        let written = tensor(case.written);
        let defect = inertia_defect(1.0, &written).expect("the test data is not physical");
        assert_eq!(defect.kind, case.kind, "{}", case.file);
    }
    // The link that moves is in the model as written (the antenna is on the base: no body).
    let as_written = load("negative-moment.urdf", NonPhysicalInertia::AsWritten).unwrap();
    let lower = body(&as_written.model, "lower");
    let moments = principal_moments(&lower.inertia_com);
    assert!((moments[0] + 1e-4).abs() < 1e-15, "{moments:?}");
}

#[test]
fn strict_refuses_each_defect_with_one_line_naming_file_place_and_link() {
    for case in CASES.iter().chain([&GROSS]) {
        let error = load_any(case.file, NonPhysicalInertia::Strict).expect_err(case.file);
        let start = format!("{}: {}: {}", data(case.place).display(), case.link, case.says);
        assert!(
            error.starts_with(&start),
            "{error}\nexpected it to start with\n{start}"
        );
        assert!(error.ends_with("; `inertia: strict` refuses it"), "{error}");
        assert!(!error.contains('\n'), "{error}");
    }
}

const GROSS: Case = Case {
    file: "gross.urdf",
    place: "gross.urdf:16:7",
    link: "link 'lower'",
    says: "inertia is not physical: triangle inequality broken by 60%: I1 + I2 = 0.004 < I3 = 0.01 kg·m²",
    kind: InertiaDefectKind::TriangleInequality,
    written: [0.002, 0.0, 0.0, 0.002, 0.0, 0.01],
};

#[test]
fn repair_gives_a_physical_inertia_no_further_from_the_written_one_than_its_defect() {
    for case in CASES.iter().chain([&GROSS]) {
        let loaded = load_any(case.file, NonPhysicalInertia::Repair).unwrap_or_else(|e| panic!("{e}"));
        assert!(loaded.warnings.is_empty(), "{}: {:?}", case.file, loaded.warnings);
        let notes: Vec<&String> = loaded.notes.iter().filter(|n| n.contains("repaired")).collect();
        assert_eq!(notes.len(), 1, "{}: {:#?}", case.file, loaded.notes);
        let note = notes[0];
        assert!(
            note.starts_with(&format!(
                "{}: {}: {}",
                data(case.place).display(),
                case.link,
                case.says
            )),
            "{note}"
        );

        // The repair as the loader does it, on the tensor as written (inertial frame).
        let written = tensor(case.written);
        let mass = if case.link == "link 'antenna'" { 1e-6 } else { 1.0 };
        let defect = inertia_defect(mass, &written).expect("not physical");
        let repaired = dyngen_codegen::model::nearest_physical(mass, &written);
        let (before, after) = (principal_moments(&written), principal_moments(&repaired));
        assert_eq!(inertia_defect(mass, &repaired), None, "{}: {after:?}", case.file);
        assert!(
            after[0] > 0.0 && after[0] + after[1] >= after[2] * (1.0 - 1e-12),
            "{after:?}"
        );
        for k in 0..3 {
            assert!(
                (after[k] - before[k]).abs() <= defect.size() * (1.0 + 1e-9),
                "{}: {before:?} → {after:?} moves more than the defect {}",
                case.file,
                defect.size()
            );
        }
        // The note gives the values before and after (exactly: the gross case, below).
        assert!(
            note.contains("repaired to the nearest physical inertia: principal moments ["),
            "{note}"
        );
        assert!(note.contains("] → ["), "{note}");

        // The model holds the repaired link: a physical body, pseudo-inertia positive
        // semi-definite (the antenna is on the base: not in the model).
        if case.link == "link 'lower'" {
            let lower = body(&loaded.model, "lower");
            assert_eq!(lower.defect(), None, "{}", case.file);
            let held = principal_moments(&lower.inertia_com);
            for k in 0..3 {
                assert!((held[k] - after[k]).abs() <= 1e-15, "{held:?} vs {after:?}");
            }
            let j = pseudo_inertia(lower);
            let smallest = j.symmetric_eigenvalues().min();
            assert!(smallest >= -1e-15 * j.amax(), "{}: pseudo-inertia {j}", case.file);
        }
    }
}

#[test]
fn a_gross_defect_is_refused_unless_repaired_or_welded_to_the_base() {
    let error = load("gross.urdf", NonPhysicalInertia::AsWritten).expect_err("60% is not rounding");
    let expected = format!(
        "{}: {}: {}, more than the 50% loaded as written: check the values (kg·m², about the centre of \
         mass), or give `inertia: repair` for the nearest physical inertia",
        data(GROSS.place).display(),
        GROSS.link,
        GROSS.says
    );
    assert_eq!(error, expected);

    // The YAML key: a wrapper that asks for the repair loads it, with the note.
    let wrapped =
        load_with(&data("gross-repaired.yaml"), &Choices::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(wrapped.warnings.is_empty(), "{:?}", wrapped.warnings);
    assert!(
        wrapped
            .notes
            .iter()
            .any(|n| n.contains("gross.urdf:16:7: link 'lower'")
                && n.contains(
                    "repaired to the nearest physical inertia: principal moments [0.002, 0.002, 0.01] \
                           → [0.004, 0.004, 0.008] kg·m²"
                )),
        "{:#?}",
        wrapped.notes
    );

    // On the base, a gross defect never enters the dynamics: as written and repaired give one model.
    let as_written = load("gross-on-base.urdf", NonPhysicalInertia::AsWritten).unwrap();
    let repaired = load("gross-on-base.urdf", NonPhysicalInertia::Repair).unwrap();
    assert!(
        as_written.warnings[0].contains("the link is welded to the fixed base and never enters the dynamics")
    );
    assert_eq!(as_written.model, repaired.model);
}

#[test]
fn an_unknown_choice_is_an_error_with_its_place() {
    let text = std::fs::read_to_string(data("triangle-inequality.yaml")).unwrap() + "inertia: repaired\n";
    let error = load_yaml_str(&text, Path::new("choice.yaml"))
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("choice.yaml:36:10: inertia: unknown variant `repaired`, expected one of"),
        "{error}"
    );
}

/// A `urdf_rs::Robot` in memory follows the same choice, with the robot named instead of a line.
#[test]
fn a_robot_in_memory_follows_the_choice() {
    let robot = urdf_rs::read_file(data("gross.urdf")).expect("urdf-rs reads it");
    let error = from_urdf_rs(&robot, &Choices::default()).unwrap_err().to_string();
    assert!(
        error.starts_with("<urdf_rs::Robot 'gross'>: link 'lower': inertia is not physical: triangle inequality broken by 60%"),
        "{error}"
    );
    let options = Choices {
        inertia: NonPhysicalInertia::Repair,
        ..Choices::default()
    };
    let repaired = from_urdf_rs(&robot, &options).unwrap_or_else(|e| panic!("{e}"));
    let from_file = load("gross.urdf", NonPhysicalInertia::Repair).unwrap();
    assert_eq!(repaired.model, from_file.model);
}

/// `Builder::inertia` for a bare URDF, or a YAML file that leaves the choice to the caller;
/// refused with a YAML file that makes it.
#[test]
fn the_builder_passes_the_choice_and_refuses_it_when_the_yaml_makes_it() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("non_physical_inertia");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("scratch");
    let builder = |file: &str| Builder::new(data(file)).out_dir(&out).cargo_directives(false);
    let refused = builder("gross.urdf")
        .compile()
        .expect_err("gross as written")
        .to_string();
    assert!(
        refused.contains("more than the 50% loaded as written"),
        "{refused}"
    );
    let written = builder("gross.urdf")
        .inertia(NonPhysicalInertia::Repair)
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(written.ends_with("gross.rs"));
    // A YAML file that leaves `inertia:` to the caller takes the builder's; one that writes
    // it refuses a second choice, naming the key at its place.
    let strict = builder("triangle-inequality.yaml")
        .inertia(NonPhysicalInertia::Strict)
        .compile()
        .expect_err("strict refuses the forearm")
        .to_string();
    assert!(strict.contains("`inertia: strict` refuses it"), "{strict}");
    let yaml = builder("gross-repaired.yaml")
        .inertia(NonPhysicalInertia::Strict)
        .compile()
        .expect_err("a YAML file that states its own choice")
        .to_string();
    assert!(
        yaml.contains("gross-repaired.yaml:3:1: `inertia` was chosen twice, by `inertia:` in the description and by the caller"),
        "{yaml}"
    );
}

/// The dynamics of links kept as written are what the Lagrangian of their kinetic and
/// potential energy says (the oracles use no dynamics algorithm), whatever the inertia.
#[test]
fn dynamics_of_non_physical_links_kept_as_written_match_the_oracles() {
    for case in &CASES[..3] {
        let loaded = load_any(case.file, NonPhysicalInertia::AsWritten).unwrap();
        let model = &loaded.model;
        let lower = body(model, "lower");
        assert!(lower.defect().is_some(), "{}: kept as written", case.file);
        let dynamics = NumericDynamics::new(model);
        for seed in 0..16 {
            let state = random_state(model, seed);
            let checks = check_all(model, &dynamics, &state);
            assert_passed(&format!("{} at seed {seed}", case.file), &checks);
        }
    }
}

/// `to_urdf_rs` writes a model's bodies as they are; a model loaded as written (slightly
/// non-physical) must come back from the file in the default mode, as the same model.
#[test]
fn exports_of_models_kept_as_written_load_back_in_the_default_mode() {
    for case in &CASES[..3] {
        let loaded = load_any(case.file, NonPhysicalInertia::AsWritten).unwrap();
        let export = to_urdf_rs(&loaded.model).unwrap_or_else(|e| panic!("{e}"));
        let text = urdf_rs::write_to_string(&export.robot).expect("written");
        let back = load_urdf_str(&text, Path::new("export.urdf"), &export.choices)
            .unwrap_or_else(|e| panic!("{}: the export is refused: {e}", case.file));
        assert_eq!(
            back.model.parameters(),
            loaded.model.parameters(),
            "{}",
            case.file
        );
        assert_eq!(
            back.warnings.iter().filter(|w| w.contains("inertia is")).count(),
            1,
            "{}: {:#?}",
            case.file,
            back.warnings
        );
    }
}
