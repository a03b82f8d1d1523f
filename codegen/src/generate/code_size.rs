//! How large a robot's generated module will be, estimated from the shape of its tree before
//! anything is traced: what decides whether dyngen generates it at all.
//!
//! Flattened code grows with the entries a function computes and with the work behind each
//! entry, which the tree's shape fixes: `D` and `C` have an entry per pair of joints one of which
//! carries the other, `D⁻¹` and forward dynamics one per pair of joints with a common ancestor
//! costing as many terms as they share, a frame's functions as many columns as joints carry
//! it, a regressor as many entries as (row, body) pairs where the row's joint carries the body.
//! The coefficients (bytes of Rust per such pair) were fitted on generated modules of chains
//! of 24, 32 and 64 joints, the G1 humanoid and TIAGo Dual (101 joints), and hold within a
//! factor of two of the bytes written for those and this repository's robots
//! (`codegen/tests/suite/code_size.rs`), which is what a guard needs. A joint count alone is no guard: a
//! 64-joint chain writes 43 MB where a 101-joint mobile manipulator, whose arms and fingers
//! branch off a short trunk, writes 12 MB.

use crate::description::{Choices, CodeShape, FrameReferences};
use crate::generate::quantities::QuantityKind;
use crate::model::Model;
use crate::{FunctionGroup, Functions};

/// The largest module dyngen writes: beyond it, tracing needs gigabytes and compiling the code
/// takes longer than anyone waits (a loaded model may have thousands of joints).
pub const MAX_GENERATED_BYTES: usize = 100_000_000;

/// The estimated bytes of Rust of each chosen group's functions.
#[derive(Clone, Debug, PartialEq)]
pub struct CodeSize {
    pub by_group: Vec<(FunctionGroup, usize)>,
}

impl CodeSize {
    /// The whole module.
    pub fn total(&self) -> usize {
        self.by_group.iter().map(|(_, bytes)| bytes).sum()
    }

    /// The group of the most code.
    pub fn largest(&self) -> Option<(FunctionGroup, usize)> {
        self.by_group.iter().copied().max_by_key(|&(_, bytes)| bytes)
    }
}

/// The sums over the tree that the sizes follow (on a floating base the base counts as six
/// joints carrying every other).
struct TreeShape {
    /// Velocity coordinates.
    nv: usize,
    /// Ordered pairs of joints one of which carries the other (the entries of `D` that are not
    /// zero).
    related_pairs: usize,
    /// `Σ` over ordered pairs of joints of the joints carrying both: `Σ_k size(k)²` over the
    /// subtrees.
    shared_ancestors: usize,
    /// `Σ` over bodies of the joints carrying it (the nonzero row blocks of a regressor).
    carried: usize,
    /// `Σ` over the named frames of the joints carrying it.
    frame_depths: usize,
    /// The end-effector's.
    end_effector_depth: usize,
}

impl TreeShape {
    fn of(model: &Model) -> TreeShape {
        let joints = model.joints();
        let n = joints.len();
        let base = if model.floating_base().is_some() { 6 } else { 0 };
        // Joints come in topological order: a parent before its children.
        let mut depth = vec![0usize; n];
        for (k, joint) in joints.iter().enumerate() {
            depth[k] = 1 + joint.parent.map_or(0, |p| depth[p]);
        }
        let mut subtree = vec![1usize; n];
        for k in (0..n).rev() {
            if let Some(p) = joints[k].parent {
                subtree[p] += subtree[k];
            }
        }
        let carried_by = |body: Option<usize>| base + body.map_or(0, |b| depth[b]);
        TreeShape {
            nv: model.nv(),
            related_pairs: depth.iter().map(|d| 2 * d - 1).sum::<usize>() + base * (2 * n + base),
            shared_ancestors: subtree.iter().map(|s| s * s).sum::<usize>() + base * n * n,
            carried: depth.iter().map(|d| d + base).sum(),
            frame_depths: model.frames().iter().map(|f| carried_by(f.parent)).sum(),
            end_effector_depth: carried_by(Some(model.end_effector_body())),
        }
    }
}

/// What every group writes whatever the robot: signatures, docs, the `_into` forms, the kernel
/// plumbing of each function; kinematics and frames, with neither `_into` forms nor lanes, a
/// third of it.
const PER_GROUP: usize = 150_000;

fn per_group(group: FunctionGroup) -> usize {
    match group {
        FunctionGroup::Kinematics | FunctionGroup::Frames => PER_GROUP / 3,
        _ => PER_GROUP,
    }
}

/// The frames' functions (every reference frame its own) above which `frame_references: auto`
/// keeps `local_world_aligned` alone as straight-line code: the frames of every link of a
/// humanoid go over (the G1's 39 write 12 MB in every reference frame, Talos' 60 23 MB), an
/// arm's every link and a few feet or hands on a humanoid stay under.
pub const FRAMES_IN_EVERY_REFERENCE_UP_TO: usize = 3_000_000;

/// What a robot's functions are written as, decided from the user's choices and the estimate
/// of their size ([`shapes`]): the reference frames of the frame functions that are
/// straight-line code, and the functions written composed.
#[derive(Clone, Debug, PartialEq)]
pub struct Shapes {
    /// `All` or `Aligned` (never `Auto`).
    pub frame_references: FrameReferences,
    /// The functions computed from smaller generated ones (`code_shape: composed`).
    pub composed: Vec<QuantityKind>,
}

impl Shapes {
    /// Every function straight-line, in every reference frame: what a small robot gets.
    pub fn flat() -> Shapes {
        Shapes {
            frame_references: FrameReferences::All,
            composed: Vec::new(),
        }
    }

    /// Whether `kind` is written composed.
    pub fn is_composed(&self, kind: QuantityKind) -> bool {
        self.composed.contains(&kind)
    }
}

/// The straight-line functions above which `code_shape: auto` writes a function composed. The
/// composed derivatives of forward dynamics cost 1.4× the straight-line ones on the G1
/// humanoid (2.3 MB of them) and 1.8× on Solo-12 (0.46 MB), so the fastest form stays the
/// default through humanoids; above (`∂q̈/∂x` of about 46 velocity coordinates, `D⁻¹` of two
/// arms with hands on a trunk) the straight-line form's megabytes and compile time decide.
pub const FLAT_FUNCTIONS_UP_TO: usize = 4_000_000;

/// The estimated bytes of `kind`'s straight-line code, for the functions that have a composed
/// form: `∂ν̇/∂x` an entry per pair of velocity coordinates, each a solve's worth of work
/// (Solo-12: 0.46 MB, the G1: 2.3 MB); `D⁻¹` an entry per pair of joints with a common
/// ancestor, a term per ancestor they share; forward dynamics the factor's work besides `D`
/// and `τ`. Written: the G1 0.74 and 0.59 MB, Talos (mimic grippers) 0.92 and 0.68 MB, TIAGo
/// Dual 4.9 and 1.7 MB; `D⁻¹` estimated 1.3, 3.1 and 6.3 MB, TIAGo Dual's forward dynamics
/// 3.3 MB.
fn flat_function_bytes(shape: &TreeShape, kind: QuantityKind) -> usize {
    match kind {
        QuantityKind::ForwardDynamicsDerivatives => 1_900 * shape.nv * shape.nv,
        QuantityKind::MassMatrixInverse => 200 * shape.shared_ancestors,
        QuantityKind::ForwardDynamics => 50 * shape.shared_ancestors + 1_000 * shape.related_pairs,
        _ => 0,
    }
}

/// The functions of the groups `functions` that `choice` writes composed, each with the
/// estimated bytes of its straight-line form: with `auto`, those above
/// [`FLAT_FUNCTIONS_UP_TO`].
pub fn composed_functions(
    model: &Model,
    functions: Functions,
    choice: CodeShape,
) -> Vec<(QuantityKind, usize)> {
    let shape = TreeShape::of(model);
    (QuantityKind::ALL.into_iter())
        .filter(|kind| kind.has_composed_form() && functions.contains(kind.group()))
        .map(|kind| (kind, flat_function_bytes(&shape, kind)))
        .filter(|&(_, bytes)| match choice {
            CodeShape::Auto => bytes > FLAT_FUNCTIONS_UP_TO,
            CodeShape::Flat => false,
            CodeShape::Composed => true,
        })
        .collect()
}

/// What `model`'s functions of the groups `functions` are written as, as `choices` ask (`auto`
/// decided by the estimated size of the code), with a note for each decision that moves a
/// function from its fastest shape.
pub fn shapes(model: &Model, functions: Functions, choices: &Choices) -> (Shapes, Vec<String>) {
    let mut notes = Vec::new();
    let chosen = choices.frame_references;
    let (frame_references, frame_bytes) = frame_references(model, functions, chosen);
    if chosen == FrameReferences::Auto && frame_references == FrameReferences::Aligned {
        notes.push(format!(
            "{} frames: their functions in every reference frame would be about {} MB of Rust, \
             so `local` and `world` are converted from `local_world_aligned` at run time \
             (`frame_references: all` writes each as a function of its own)",
            model.frames().len(),
            frame_bytes / 1_000_000
        ));
    }
    let composed = composed_functions(model, functions, choices.code_shape);
    if choices.code_shape == CodeShape::Auto {
        notes.extend(composed.iter().map(|&(kind, bytes)| {
            format!(
                "`{}` as straight-line code would be about {:.1} MB of Rust, so it is computed \
                 from the robot's smaller functions through the tree factor of `D` \
                 (`code_shape: flat` writes it whole)",
                kind.name(),
                bytes as f64 / 1e6
            )
        }));
    }
    let shapes = Shapes {
        frame_references,
        composed: composed.into_iter().map(|(kind, _)| kind).collect(),
    };
    (shapes, notes)
}

/// The estimated size of `model`'s module with the groups `functions`, written as `shapes`
/// says.
pub fn estimate(model: &Model, functions: Functions, shapes: &Shapes) -> CodeSize {
    let shape = TreeShape::of(model);
    let by_group = (functions.groups())
        .map(|group| {
            let bytes = match (group, shapes.frame_references) {
                // Base axes alone: about a third of the three references' code (the G1's
                // and Talos' frames of every link).
                (FunctionGroup::Frames, FrameReferences::Aligned) => 7_500 * shape.frame_depths,
                _ => group_bytes(model, &shape, group),
            };
            let composed: usize = (shapes.composed.iter())
                .filter(|kind| kind.group() == group)
                .map(|&kind| flat_function_bytes(&shape, kind))
                .sum();
            // A group whose every function is a call has little besides its signatures.
            let mut kinds = QuantityKind::ALL.into_iter().filter(|kind| kind.group() == group);
            let overhead = match kinds.all(|kind| shapes.is_composed(kind)) {
                true => per_group(group) / 10,
                false => per_group(group),
            };
            (group, overhead + bytes.saturating_sub(composed))
        })
        .collect();
    CodeSize { by_group }
}

/// The bytes of one group's functions beyond [`per_group`], every frame function in every
/// reference frame.
fn group_bytes(model: &Model, shape: &TreeShape, group: FunctionGroup) -> usize {
    match group {
        FunctionGroup::Kinematics => 9_000 * shape.end_effector_depth,
        FunctionGroup::Dynamics => 1_850 * shape.related_pairs,
        FunctionGroup::Regressors | FunctionGroup::BaseParameters => 7_000 * shape.carried,
        FunctionGroup::ForwardDynamics => {
            flat_function_bytes(shape, QuantityKind::MassMatrixInverse)
                + flat_function_bytes(shape, QuantityKind::ForwardDynamics)
        }
        FunctionGroup::Derivatives => 3_500 * shape.nv * shape.nv + 100 * shape.shared_ancestors,
        FunctionGroup::Frames => 23_000 * shape.frame_depths,
        FunctionGroup::Contacts => 2_000 * model.contact_rows() * shape.nv,
    }
}

/// What `choice` writes for `model`: `auto` decided by the estimated size of the frames'
/// functions in every reference frame ([`FRAMES_IN_EVERY_REFERENCE_UP_TO`]), with that estimate.
pub fn frame_references(
    model: &Model,
    functions: Functions,
    choice: FrameReferences,
) -> (FrameReferences, usize) {
    let bytes = match functions.contains(FunctionGroup::Frames) {
        true => group_bytes(model, &TreeShape::of(model), FunctionGroup::Frames),
        false => 0,
    };
    let resolved = match choice {
        FrameReferences::Auto if bytes > FRAMES_IN_EVERY_REFERENCE_UP_TO => FrameReferences::Aligned,
        FrameReferences::Auto => FrameReferences::All,
        chosen => chosen,
    };
    (resolved, bytes)
}
