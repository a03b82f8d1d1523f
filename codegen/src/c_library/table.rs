//! The C library's table of functions: one entry per generated quantity the robot has, and per
//! reference frame for the frame quantities that have one, each with its inputs and outputs
//! named and sized. Everything here follows from the quantity table
//! ([`QuantityKind::signature`]) and the robot's sizes: the wrapper, the header and the
//! table a binding reads are all written from these entries.

use crate::generate::quantities::{Arg, Dims, QuantityKind, Shape};
use crate::generate::trace_floating::floating_kinds;
use crate::{FunctionGroup, Functions};
use dyngen_runtime::ReferenceFrame;

/// The sizes a robot's C interface publishes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Sizes {
    pub floating: bool,
    pub dof: usize,
    pub nq: usize,
    pub nv: usize,
    pub parameters: usize,
    pub base_parameters: usize,
    pub frames: usize,
    /// Contact rows (0 without contacts).
    pub contact_rows: usize,
}

/// A size as the header spells it: one of the robot's sizes, or a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Size {
    Nq,
    Nv,
    Parameters,
    BaseParameters,
    ContactRows,
    Number(usize),
}

/// One input (`rows × 1`) or output (`rows × cols`, column-major) of one state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Array {
    pub name: &'static str,
    pub rows: usize,
    pub cols: usize,
    /// `rows` and `cols` as the header spells them (`NV`, not 7).
    pub spelled: [Size; 2],
    /// What it holds, for the header.
    pub about: &'static str,
}

impl Array {
    fn new(name: &'static str, rows: usize, cols: usize, about: &'static str) -> Array {
        Array {
            name,
            rows,
            cols,
            spelled: [Size::Number(rows), Size::Number(cols)],
            about,
        }
    }

    /// Doubles per state.
    pub fn len(&self) -> usize {
        self.rows * self.cols
    }
}

/// One function of the C library.
#[derive(Clone, Debug)]
pub(super) struct Entry {
    pub kind: QuantityKind,
    /// The reference frame of a frame quantity that has one.
    pub reference: Option<ReferenceFrame>,
    /// The arguments besides the configuration, as the quantity table gives them.
    pub args: Vec<Arg>,
    pub shape: Shape,
    /// `q` first, then one per argument.
    pub inputs: Vec<Array>,
    pub outputs: Vec<Array>,
    /// States computed per call by a batch: 4 where the robot has the lane form.
    pub lanes: usize,
}

impl Entry {
    /// The function's name after the prefix: the quantity's, then the reference frame's
    /// (`frame_jacobian_local`).
    pub fn name(&self) -> String {
        match self.reference {
            Some(r) => format!("{}_{}", self.kind.name(), r.keyword()),
            None => self.kind.name().to_owned(),
        }
    }

    /// Whether it takes a frame index.
    pub fn takes_frame(&self) -> bool {
        self.kind.is_per_frame()
    }
}

/// The reference frame's number in the C interface (`DYNGEN_LOCAL` …), or -1 for none.
pub(super) fn reference_number(reference: Option<ReferenceFrame>) -> i32 {
    match reference {
        None => -1,
        Some(ReferenceFrame::Local) => 0,
        Some(ReferenceFrame::World) => 1,
        Some(ReferenceFrame::LocalWorldAligned) => 2,
    }
}

/// The quantities the robot was generated with: those of one state in the generated module's
/// order, the contacts' rows, then the per-frame ones.
fn kinds(sizes: &Sizes, functions: &Functions) -> Vec<QuantityKind> {
    let generated = |k: &QuantityKind| functions.contains(k.group());
    let per_frame = (QuantityKind::ALL.into_iter()).filter(|k| k.is_per_frame() && generated(k));
    let one_state: Vec<QuantityKind> = match sizes.floating {
        true => floating_kinds().filter(generated).collect(),
        false => (QuantityKind::ALL.into_iter())
            .filter(|k| !k.is_per_frame() && generated(k))
            .collect(),
    };
    // The derivatives' pieces are what the runtime's `constrained_forward_dynamics_derivatives`
    // assembles, and the one-call solves what its solves check and refine; the library exports
    // the runtime's solves, not their pieces.
    let pieces = [
        QuantityKind::ContactForwardDynamicsDerivatives,
        QuantityKind::ContactAccelerationDerivatives,
        QuantityKind::ContactSolve,
        QuantityKind::ContactProximalSolve,
        QuantityKind::ContactImpulse,
        QuantityKind::ContactForwardDynamics,
        QuantityKind::ContactInertia,
    ];
    let contacts = (QuantityKind::CONTACTS.into_iter())
        .filter(generated)
        .filter(|k| !pieces.contains(k));
    one_state.into_iter().chain(contacts).chain(per_frame).collect()
}

/// Sizes no robot has, each standing for one of the robot's: the quantity table's shapes in
/// these sizes say which of its sizes each number is (a 6-DOF arm's `J` is `6 × NV`, not
/// `NV × NV`).
const SPELLING: Sizes = Sizes {
    floating: false,
    dof: 0,
    nq: usize::MAX - 3,
    nv: usize::MAX - 2,
    parameters: usize::MAX - 1,
    base_parameters: usize::MAX,
    frames: 0,
    contact_rows: usize::MAX - 4,
};

fn spelled(n: usize) -> Size {
    match n {
        _ if n == SPELLING.nq => Size::Nq,
        _ if n == SPELLING.nv => Size::Nv,
        _ if n == SPELLING.parameters => Size::Parameters,
        _ if n == SPELLING.base_parameters => Size::BaseParameters,
        _ if n == SPELLING.contact_rows => Size::ContactRows,
        n => Size::Number(n),
    }
}

/// Every entry of the robot's table, in order, its sizes spelled as the header spells them.
pub(super) fn entries(sizes: &Sizes, functions: &Functions) -> Vec<Entry> {
    let spelling = Sizes {
        floating: sizes.floating,
        ..SPELLING
    };
    let mut entries = entries_in(sizes, functions);
    for (entry, symbolic) in entries.iter_mut().zip(entries_in(&spelling, functions)) {
        let arrays = entry.inputs.iter_mut().chain(&mut entry.outputs);
        for (array, symbolic) in arrays.zip(symbolic.inputs.iter().chain(&symbolic.outputs)) {
            array.spelled = [spelled(symbolic.rows), spelled(symbolic.cols)];
        }
    }
    entries
}

/// The entries in the sizes `sizes`.
fn entries_in(sizes: &Sizes, functions: &Functions) -> Vec<Entry> {
    let dims = Dims {
        n: sizes.nv,
        p: sizes.parameters,
        b: sizes.base_parameters,
        c: sizes.contact_rows,
    };
    // The lane forms come with the base parameters, on a fixed base.
    let lanes = !sizes.floating && functions.contains(FunctionGroup::BaseParameters);
    let mut entries = Vec::new();
    for kind in kinds(sizes, functions) {
        let references = match kind.has_reference_frame() {
            true => ReferenceFrame::ALL.map(Some).to_vec(),
            false => vec![None],
        };
        for reference in references {
            let (args, shape) = kind.signature(dims);
            let configuration = match sizes.floating {
                true => Array::new(
                    "q",
                    sizes.nq,
                    1,
                    "the configuration q: the base position (m) and unit quaternion x y z w, then \
                     the joint positions (rad or m)",
                ),
                false => Array::new("q", sizes.nq, 1, "the joint positions q (rad or m)"),
            };
            let inputs = std::iter::once(configuration)
                .chain(args.iter().map(|&arg| input(kind, arg, &args, sizes)))
                .collect();
            entries.push(Entry {
                kind,
                reference,
                outputs: outputs(kind, shape),
                args,
                shape,
                inputs,
                lanes: if lanes && kind.has_lane_form() { 4 } else { 1 },
            });
        }
    }
    entries
}

/// The input that carries `arg` (one of `args`, a function of `kind`).
fn input(kind: QuantityKind, arg: Arg, args: &[Arg], sizes: &Sizes) -> Array {
    let nv = sizes.nv;
    let floating = sizes.floating;
    match arg {
        Arg::Qd if floating => Array::new(
            "qd",
            nv,
            1,
            "the velocity ν: the base twist [v; ω] in the base frame (m/s, rad/s), then the \
             joint rates",
        ),
        Arg::Qd => Array::new("qd", nv, 1, "the joint velocities q̇ (rad/s or m/s)"),
        Arg::V => Array::new("v", nv, 1, "the reference velocity v"),
        // The acceleration is the reference one where a reference velocity comes with it.
        Arg::A if args.contains(&Arg::V) => Array::new("a", nv, 1, "the reference acceleration a"),
        Arg::A if floating => Array::new("qdd", nv, 1, "the acceleration ν̇, laid out as ν"),
        Arg::A => Array::new("qdd", nv, 1, "the joint accelerations q̈ (rad/s² or m/s²)"),
        Arg::Tau if floating => Array::new(
            "tau",
            nv,
            1,
            "the generalised force: the base wrench [f; n] in the base frame (N, N·m), then \
             the joint torques",
        ),
        Arg::Tau => Array::new("tau", nv, 1, "the joint torques τ (N·m or N)"),
        Arg::Theta(len) if kind.uses_base_columns() => {
            Array::new("base_parameters", len, 1, "the base parameters θ_b")
        }
        Arg::Theta(len) => Array::new(
            "parameters",
            len,
            1,
            "the standard parameters θ (ten per body, as P_parameters gives them)",
        ),
        Arg::R => Array::new("r", nv, 1, "the vector r that Yᵀ multiplies"),
        Arg::Forces(len) => Array::new(
            "lambda",
            len,
            1,
            "the contact forces λ, one per contact row, as the contact solves give them",
        ),
        Arg::Target(len) => Array::new(
            "target",
            len,
            1,
            "what the contact rows' acceleration is asked to be besides its feedback terms",
        ),
        Arg::Coefficient(c) => Array::new(c.name(), 1, 1, "a coefficient of the contact solve"),
    }
}

/// What a function of `kind` returning `shape` writes, one array per part.
fn outputs(kind: QuantityKind, shape: Shape) -> Vec<Array> {
    let rotation = Array::new(
        "rotation",
        3,
        3,
        "the frame's axes in base coordinates, as columns",
    );
    let translation = Array::new("translation", 3, 1, "the frame's origin (m)");
    match shape {
        Shape::Vector(n) => vec![Array::new(kind.name(), n, 1, "")],
        Shape::Matrix(rows, cols) => vec![Array::new(kind.name(), rows, cols, "")],
        Shape::Pose => vec![rotation, translation],
        Shape::MatrixPair(rows, cols) => vec![
            Array::new("d_dq", rows, cols, "the derivative with respect to q"),
            Array::new("d_dqd", rows, cols, "the derivative with respect to q̇"),
        ],
        Shape::Kinematics(n) => vec![
            rotation,
            translation,
            Array::new("jacobian", 6, n, "J, rows [linear; angular]"),
            Array::new("jacobian_dot", 6, n, "J̇"),
        ],
        Shape::VectorPair(n, m) => vec![
            Array::new("y_theta", n, 1, "Y θ"),
            Array::new("yt_r", m, 1, "Yᵀ r"),
        ],
        Shape::ContactMatrices(n, c) => contact_matrices(n, c),
        Shape::ContactSystem(n, c) => {
            let mut arrays = contact_matrices(n, c);
            arrays.extend([
                Array::new("contact_drift", c, 1, "the rows' drift along q̇"),
                Array::new("free_acceleration", n, 1, "forward dynamics without contacts"),
            ]);
            arrays
        }
        Shape::ContactStep(n, c) => vec![
            Array::new(
                "acceleration",
                n,
                1,
                "the acceleration (the velocity after, for an impact)",
            ),
            Array::new("forces", c, 1, "the contact forces λ"),
            Array::new("previous_forces", c, 1, "the forces of the step before"),
            Array::new("contact_delassus", c, c, "the Delassus matrix J D⁻¹ Jᵀ"),
            Array::new("pivots", c, 1, "the pivots of K + μ I"),
            Array::new("rhs", c, 1, "what K λ must equal"),
        ],
        Shape::ContactInertia(c) => vec![
            Array::new("inertia", c, c, "(K + ε I)⁻¹"),
            Array::new("pivots", c, 1, "the pivots of K + ε I"),
            Array::new("delassus_diagonal", c, 1, "K's diagonal"),
        ],
    }
}

/// The parts of `ContactMatrices` of `n` velocity coordinates and `c` contact rows.
fn contact_matrices(n: usize, c: usize) -> Vec<Array> {
    vec![
        Array::new("contact_jacobian", c, n, "J, the contacts' rows"),
        Array::new("contact_response", n, c, "D⁻¹ Jᵀ"),
        Array::new("contact_delassus", c, c, "the Delassus matrix J D⁻¹ Jᵀ"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed-base arm of `dof` joints (ten parameters each, `base` base parameters), two
    /// frames and `contact_rows`.
    fn fixed_arm(dof: usize, base: usize, contact_rows: usize) -> Sizes {
        Sizes {
            floating: false,
            dof,
            nq: dof,
            nv: dof,
            parameters: 10 * dof,
            base_parameters: base,
            frames: 2,
            contact_rows,
        }
    }

    fn arm(functions: Functions) -> Vec<Entry> {
        entries(&fixed_arm(7, 43, 0), &functions)
    }

    #[test]
    fn names_are_distinct_and_inputs_and_outputs_distinct_within_a_function() {
        let entries = arm(Functions::all());
        let mut names: Vec<String> = entries.iter().map(Entry::name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), entries.len());
        for e in &entries {
            let mut arrays: Vec<&str> = e.inputs.iter().chain(&e.outputs).map(|a| a.name).collect();
            arrays.sort();
            arrays.dedup();
            assert_eq!(arrays.len(), e.inputs.len() + e.outputs.len(), "{}", e.name());
        }
    }

    #[test]
    fn every_generated_quantity_is_an_entry_and_frames_come_last() {
        let entries = arm(Functions::all());
        for kind in QuantityKind::ALL {
            assert!(entries.iter().any(|e| e.kind == kind), "{kind:?}");
        }
        let first_frame = entries.iter().position(Entry::takes_frame).expect("frames");
        assert!(entries[first_frame..].iter().all(Entry::takes_frame));
        // Three reference frames for the Jacobian, one for the pose.
        assert_eq!(
            entries
                .iter()
                .filter(|e| e.kind == QuantityKind::FrameJacobian)
                .count(),
            3
        );
        assert_eq!(
            entries
                .iter()
                .filter(|e| e.kind == QuantityKind::FramePose)
                .count(),
            1
        );
    }

    #[test]
    fn contact_rows_are_entries_before_the_frames_and_spelled_nc() {
        // A 6-DOF arm holding its end-effector as a frame and another point: 9 rows.
        let sizes = fixed_arm(6, 36, 9);
        let entries = entries(&sizes, &Functions::all());
        let names: Vec<String> = entries.iter().map(Entry::name).collect();
        let at = |name: &str| names.iter().position(|n| n == name).expect(name);
        let first_frame = entries.iter().position(Entry::takes_frame).expect("frames");
        let rows = [
            "contact_jacobian",
            "contact_drift",
            "contact_response",
            "contact_delassus",
            "contact_matrices",
            "contact_system",
        ];
        assert_eq!(rows.map(at), [6, 5, 4, 3, 2, 1].map(|k| first_frame - k));
        let arrays = |name: &str| {
            let e = &entries[at(name)];
            let inputs: Vec<&str> = e.inputs.iter().map(|a| a.name).collect();
            let outputs: Vec<_> = e
                .outputs
                .iter()
                .map(|a| (a.name, a.rows, a.cols, a.spelled))
                .collect();
            (inputs, outputs)
        };
        let (nc, nv) = (Size::ContactRows, Size::Nv);
        assert_eq!(
            arrays("contact_jacobian"),
            (vec!["q"], vec![("contact_jacobian", 9, 6, [nc, nv])])
        );
        assert_eq!(
            arrays("contact_drift"),
            (
                vec!["q", "qd"],
                vec![("contact_drift", 9, 1, [nc, Size::Number(1)])]
            )
        );
        assert_eq!(
            arrays("contact_response"),
            (vec!["q"], vec![("contact_response", 6, 9, [nv, nc])])
        );
        assert_eq!(
            arrays("contact_delassus"),
            (vec!["q"], vec![("contact_delassus", 9, 9, [nc, nc])])
        );
        // The one-call rows: their parts, each under the name of the row it repeats.
        let (inputs, outputs) = arrays("contact_system");
        assert_eq!(inputs, ["q", "qd", "tau"]);
        assert_eq!(
            outputs,
            [
                ("contact_jacobian", 9, 6, [nc, nv]),
                ("contact_response", 6, 9, [nv, nc]),
                ("contact_delassus", 9, 9, [nc, nc]),
                ("contact_drift", 9, 1, [nc, Size::Number(1)]),
                ("free_acceleration", 6, 1, [nv, Size::Number(1)]),
            ]
        );
        assert_eq!(arrays("contact_matrices").1, outputs[..3]);
        // Without the group, none.
        let without = super::entries(&sizes, &Functions::all().without(FunctionGroup::Contacts));
        assert!(without.iter().all(|e| e.kind.group() != FunctionGroup::Contacts));
    }

    #[test]
    fn lanes_only_with_the_base_parameters() {
        let with = arm(Functions::all());
        let lanes: Vec<String> = with.iter().filter(|e| e.lanes == 4).map(Entry::name).collect();
        assert_eq!(lanes, ["inverse_dynamics", "base_torque_regressor"]);
        let without = arm(Functions::with(&[]).expect("kinematics and dynamics"));
        assert!(without.iter().all(|e| e.lanes == 1));
        assert!(without.iter().all(|e| !e.takes_frame()));
    }

    #[test]
    fn inputs_are_named_by_what_they_are() {
        let entries = arm(Functions::all());
        let inputs = |name: &str| -> Vec<(&str, usize)> {
            let e = entries.iter().find(|e| e.name() == name).expect(name);
            e.inputs.iter().map(|a| (a.name, a.rows)).collect()
        };
        assert_eq!(inputs("inverse_dynamics"), [("q", 7), ("qd", 7), ("qdd", 7)]);
        assert_eq!(inputs("slotine_li"), [("q", 7), ("qd", 7), ("v", 7), ("a", 7)]);
        assert_eq!(
            inputs("base_regressor_products"),
            [
                ("q", 7),
                ("qd", 7),
                ("v", 7),
                ("a", 7),
                ("base_parameters", 43),
                ("r", 7)
            ]
        );
        assert_eq!(inputs("regressor_products")[4], ("parameters", 70));
    }

    #[test]
    fn sizes_are_spelled_by_what_they_are_not_by_value() {
        // A 6-DOF arm: its Jacobian is 6 × NV, not NV × NV.
        let sizes = fixed_arm(6, 36, 0);
        let entries = entries(&sizes, &Functions::all());
        let jacobian = entries.iter().find(|e| e.name() == "jacobian").expect("J");
        assert_eq!(jacobian.outputs[0].spelled, [Size::Number(6), Size::Nv]);
        assert_eq!((jacobian.outputs[0].rows, jacobian.outputs[0].cols), (6, 6));
        assert_eq!(jacobian.inputs[0].spelled, [Size::Nq, Size::Number(1)]);
        let y_b = entries
            .iter()
            .find(|e| e.name() == "base_regressor")
            .expect("Y_b");
        assert_eq!(y_b.outputs[0].spelled, [Size::Nv, Size::BaseParameters]);
    }
}
