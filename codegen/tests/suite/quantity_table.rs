//! The table of generated functions (`QuantityKind`) against what it describes: the tracer records
//! exactly its kinds in its order, the traits of `dyngen-runtime` declare each function in the
//! trait of its group (and nothing generated that the table misses), the lane forms exist, and the
//! reference in `docs/dynamics.md` names every function.

use dyngen_codegen::description::load;
use dyngen_codegen::internals::generate::{trace, QuantityKind};
use dyngen_codegen::FunctionGroup;
use dyngen_testkit::workspace_root;
use std::collections::BTreeSet;

/// The required and provided methods of trait `name` in a runtime source file.
fn trait_methods(file: &str, name: &str) -> BTreeSet<String> {
    let path = workspace_root().join("runtime/src").join(file);
    let source = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let parsed = syn::parse_file(&source).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let methods: Option<BTreeSet<String>> = parsed.items.iter().find_map(|item| match item {
        syn::Item::Trait(t) if t.ident == name => Some(
            t.items
                .iter()
                .filter_map(|i| match i {
                    syn::TraitItem::Fn(f) => Some(f.sig.ident.to_string()),
                    _ => None,
                })
                .collect(),
        ),
        _ => None,
    });
    methods.unwrap_or_else(|| panic!("no trait {name} in {}", path.display()))
}

#[test]
fn the_tracer_records_the_table_in_its_order() {
    for robot in ["arm7.yaml", "arm7_friction.yaml", "ur5.yaml"] {
        let model = load(&workspace_root().join("robots").join(robot))
            .unwrap_or_else(|e| panic!("{e}"))
            .model;
        let mut traced: Vec<QuantityKind> = trace(&model).quantities.iter().map(|q| q.kind).collect();
        // A frame quantity comes once per reference frame, and the frames one after another.
        let frames = model.frames().len();
        let per_frame = traced.iter().filter(|k| k.is_per_frame()).count() / frames;
        traced.truncate(traced.len() - per_frame * (frames - 1));
        traced.dedup();
        assert_eq!(traced, QuantityKind::ALL.to_vec(), "{robot}");
    }
}

/// The name of a function's `_into` form (written into a `ResultBuffer`).
fn into_form(name: &str) -> String {
    format!("{name}_into")
}

/// The `_into` forms of `kinds` that have one.
fn into_forms(kinds: &[QuantityKind]) -> BTreeSet<String> {
    kinds
        .iter()
        .filter(|k| k.has_into_form())
        .map(|k| into_form(k.name()))
        .collect()
}

#[test]
fn each_function_is_declared_by_the_trait_of_its_group() {
    let file = |group: FunctionGroup| match group {
        FunctionGroup::BaseParameters => "parameterization.rs",
        FunctionGroup::Frames => "frames.rs",
        FunctionGroup::Contacts => "contacts/robot.rs",
        _ => "robot.rs",
    };
    let traits: Vec<(FunctionGroup, BTreeSet<String>)> = FunctionGroup::ALL
        .into_iter()
        .map(|g| (g, trait_methods(file(g), g.trait_name())))
        .collect();
    for kind in QuantityKind::ALL.into_iter().chain(QuantityKind::CONTACTS) {
        for (group, methods) in &traits {
            assert_eq!(
                methods.contains(kind.name()),
                kind.group() == *group,
                "{}: the table puts it in {:?}",
                kind.name(),
                kind.group()
            );
            assert_eq!(
                methods.contains(&into_form(kind.name())),
                kind.group() == *group && kind.has_into_form(),
                "{}: its `_into` form against the table",
                kind.name()
            );
        }
    }
    // What the traits declare beyond the table is not traced: the parameter vectors, which the
    // emitter writes from the model's numbers, the torques of external wrenches, which the
    // runtime forms from the frames' Jacobians, and what a robot with contacts calls of its
    // other traits (forward dynamics and `M⁻¹`, the frames' poses and local Jacobians).
    let from_numbers = [
        "parameters",
        "base_parameters",
        "wrench_torques",
        "free_acceleration",
        "torque_response",
        "contact_pose",
        "contact_to_pose",
        "contact_local_jacobian",
    ];
    for (group, methods) in &traits {
        for method in methods {
            let kind = QuantityKind::from_name(method.strip_suffix("_into").unwrap_or(method));
            assert!(
                kind.is_some() || from_numbers.contains(&method.as_str()),
                "{} declares {method}, which the table of generated functions lacks",
                group.trait_name()
            );
        }
    }
    let lanes = trait_methods("lanes.rs", "LaneDynamics");
    let expected: BTreeSet<String> = QuantityKind::ALL
        .into_iter()
        .filter(|k| k.has_lane_form())
        .map(|k| format!("{}_lanes", k.name()))
        .collect();
    assert_eq!(lanes, expected, "LaneDynamics against the table's lane forms");
}

#[test]
fn the_reference_names_every_function() {
    let path = workspace_root().join("docs/dynamics.md");
    let docs = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    for kind in QuantityKind::ALL {
        let name = kind.name();
        assert!(
            docs.contains(&format!("`{name}(")) || docs.contains(&format!("`{name}`")),
            "docs/dynamics.md does not name `{name}`"
        );
    }
}

#[test]
fn the_floating_traits_declare_what_a_floating_robot_is_traced_with() {
    let model = load(&workspace_root().join("robots/solo12.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let traced = trace(&model);
    let kinds: Vec<QuantityKind> = traced.quantities.iter().map(|q| q.kind).collect();
    // Each function, and its `_into` form where it has one.
    let names = |kinds: Vec<QuantityKind>| -> BTreeSet<String> {
        let mut names = into_forms(&kinds);
        names.extend(kinds.into_iter().map(|k| k.name().to_owned()));
        names
    };
    let of_group = |group: FunctionGroup| -> BTreeSet<String> {
        names(kinds.iter().copied().filter(|k| k.group() == group).collect())
    };
    // Every group but the contacts' (whose trait is one for both bases) and the kinematics'
    // (whose end-effector functions a floating base has among its frames').
    for group in FunctionGroup::ALL {
        let (Some(name), false) = (group.floating_trait_name(), group == FunctionGroup::Contacts) else {
            continue;
        };
        let mut expected = of_group(group);
        match group {
            FunctionGroup::Dynamics => {
                expected.insert("parameters".to_owned());
            }
            FunctionGroup::BaseParameters => {
                expected.insert("base_parameters".to_owned());
            }
            _ => {}
        }
        assert_eq!(
            trait_methods("floating_robot.rs", name),
            expected,
            "{name} against the group `{group}`"
        );
    }
    let contacts: Vec<QuantityKind> = (kinds.iter().copied())
        .filter(|k| k.group() == FunctionGroup::Contacts)
        .collect();
    let mut expected = names(contacts);
    let delegated = [
        "free_acceleration",
        "torque_response",
        "contact_pose",
        "contact_to_pose",
        "contact_local_jacobian",
    ];
    expected.extend(delegated.map(String::from));
    assert_eq!(
        trait_methods("contacts/robot.rs", "ContactDynamics"),
        expected,
        "ContactDynamics against the contacts' functions (Solo-12 holds its feet)"
    );
    for kind in QuantityKind::FLOATING_ONLY
        .into_iter()
        .chain(QuantityKind::CONTACTS)
    {
        assert_eq!(QuantityKind::from_name(kind.name()), Some(kind));
    }
}
