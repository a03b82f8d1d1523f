//! The crate root of a C library (`src/lib.rs`): `extern "C"` functions around the generated
//! module, written from the table's entries. Each entry becomes a function of one state (its
//! inputs read in place, its outputs written from the generated function's values), the
//! exported function that checks its pointers and calls it, and the batch loop `P_evaluate`
//! calls; the pointers are read and written in a few helpers whose contracts the callers'
//! `SAFETY` comments meet. Nothing here indexes, unwraps or allocates.

use super::table::{reference_number, Array, Entry};
use super::{contacts, Library};
use crate::generate::quantities::{Arg, Shape};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// The module of the generated robot inside the crate (`src/robot.rs`).
pub(super) const ROBOT_MODULE: &str = "robot";

/// `src/lib.rs`, formatted.
pub(super) fn crate_root(library: &Library) -> String {
    let items = [
        preamble(library),
        helpers(library),
        metadata(library),
        table(library),
        functions(library),
        evaluate(library),
        contacts::wrapper_items(library),
    ];
    let tokens: TokenStream = items.into_iter().collect();
    let file: syn::File = match syn::parse2(tokens) {
        Ok(file) => file,
        Err(e) => panic!("dyngen emitted an invalid C library wrapper ({e}); this is a bug in dyngen"),
    };
    format!(
        "{}\n// The C interface of `{}`: see `include/{}` for each function's contract.\n\
         // Do not edit by hand: regenerate with `{}`.\n\n{}",
        crate::generate::GENERATED_MARKER,
        library.robot_name,
        library.header_name(),
        library.regenerate,
        with_comments(&prettyplease::unparse(&file))
    )
}

/// Tokens carry no comments: the wrapper writes each as a statement
/// `__dyngen_comment!("…");`, which this turns into `// …` lines once formatted.
fn with_comments(formatted: &str) -> String {
    let mut out = String::with_capacity(formatted.len());
    let mut lines = formatted.lines();
    while let Some(line) = lines.next() {
        let indent = &line[..line.len() - line.trim_start().len()];
        let text = match line.trim_start() {
            // Too long for one line, prettyplease puts the text on the next and `);` after.
            "__dyngen_comment!(" => {
                let text = lines.next().map(str::trim);
                let _close = lines.next();
                text.and_then(|t| t.strip_prefix('"'))
                    .and_then(|t| t.strip_suffix('"'))
            }
            line => (line.strip_prefix("__dyngen_comment!(\"")).and_then(|rest| rest.strip_suffix("\");")),
        };
        match text {
            Some(text) => {
                for wrapped in wrap(text, 96 - indent.len()) {
                    out += &format!("{indent}// {wrapped}\n");
                }
            }
            None => {
                out += line;
                out.push('\n');
            }
        }
    }
    out
}

/// `text` in lines of at most `width` characters, broken between words.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let line = lines.last_mut().map_or(0, |l| l.chars().count());
        if line > 0 && line + 1 + word.chars().count() > width {
            lines.push(String::new());
        }
        if let Some(last) = lines.last_mut() {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

/// The `C` string literal of `text`: a reference to its first byte, NUL-terminated.
fn c_string(text: &str) -> TokenStream {
    let mut bytes = text.as_bytes().to_vec();
    bytes.push(0);
    let literal = Literal::byte_string(&bytes);
    quote!(&#literal[0])
}

fn usize(n: usize) -> Literal {
    Literal::usize_unsuffixed(n)
}

/// The attributes, the module, the status codes and the lengths.
fn preamble(library: &Library) -> TokenStream {
    let module = format_ident!("{ROBOT_MODULE}");
    let attributes: TokenStream = crate::generate::emit::MODULE_ATTRIBUTES
        .parse()
        .unwrap_or_default();
    let s = &library.sizes;
    let [dof, nq, nv, p, b] = [s.dof, s.nq, s.nv, s.parameters, s.base_parameters].map(usize);
    let nq_check = match s.floating {
        true => quote!(
            const _: () = assert!(robot::NQ == NQ && robot::NV == NV);
        ),
        false => quote!(),
    };
    quote! {
        #![allow(clippy::too_many_arguments)]
        __dyngen_comment!("The allow above: an exported function takes every input and output of its quantity (the regressor products eight pointers).");

        use core::mem::MaybeUninit;
        use dyngen_runtime::nalgebra::{SMatrix, SVector};
        use dyngen_runtime::prelude::*;

        /// The generated robot.
        #attributes
        pub mod #module;

        /// The status codes of `dyngen.h`.
        const OK: i32 = 0;
        const NULL_POINTER: i32 = 1;
        const NON_UNIT_QUATERNION: i32 = 2;
        const FRAME_OUT_OF_RANGE: i32 = 3;
        const FUNCTION_OUT_OF_RANGE: i32 = 4;
        const NOT_GENERATED: i32 = 5;
        const CONTACT_SETTINGS: i32 = 6;
        const REDUNDANT_CONTACTS: i32 = 7;

        const DOF: usize = #dof;
        const NQ: usize = #nq;
        const NV: usize = #nv;
        const PARAMETER_COUNT: usize = #p;
        const BASE_PARAMETER_COUNT: usize = #b;
        __dyngen_comment!("The sizes the header publishes are the generated module's.");
        const _: () = assert!(robot::DOF == DOF && robot::PARAMETER_COUNT == PARAMETER_COUNT);
        const _: () = assert!(robot::BASE_PARAMETER_COUNT == BASE_PARAMETER_COUNT);
        #nq_check
    }
}

/// Reading and writing through the caller's pointers, the configuration, and the lanes.
fn helpers(library: &Library) -> TokenStream {
    let floating = library.sizes.floating;
    let trig = match floating {
        true => quote! {
            /// The configuration prepared for the generated functions; a quaternion that is not
            /// a unit one is refused.
            #[inline(always)]
            fn trig(q: &SVector<f64, NQ>) -> Result<FloatingTrig<DOF>, i32> {
                FloatingTrig::from_configuration(q.as_slice()).map_err(|_| NON_UNIT_QUATERNION)
            }

            /// Whether every state's quaternion is a unit one, checked before a batch writes
            /// anything.
            ///
            /// # Safety
            /// `q` points to `batch` configurations of `NQ` doubles.
            unsafe fn check_configurations(q: *const f64, batch: usize) -> Result<(), i32> {
                for s in 0..batch {
                    let mut copy = MaybeUninit::uninit();
                    __dyngen_comment!("SAFETY: state `s` lies within the `batch` states the caller provides.");
                    trig(unsafe { input::<NQ>(q.add(NQ * s), &mut copy) })?;
                }
                Ok(())
            }
        },
        false => quote! {
            /// The configuration prepared for the generated functions (its sines and cosines).
            #[inline(always)]
            fn trig(q: &SVector<f64, NQ>) -> Result<JointTrig<DOF>, i32> {
                Ok(JointTrig::new(q))
            }
        },
    };
    let lanes = match library.entries.iter().any(|e| e.lanes > 1) {
        true => quote! {
            use dyngen_runtime::{f64x4, JointTrigLanes};

            /// Four consecutive states of a vector of `R` entries, one per lane.
            ///
            /// # Safety
            /// `p` points to `4 · R` readable doubles.
            unsafe fn read_lanes<const R: usize>(p: *const f64) -> [f64x4; R] {
                __dyngen_comment!("SAFETY: passed on from the caller.");
                let [s0, s1, s2, s3] = unsafe { p.cast::<[[f64; R]; 4]>().read_unaligned() };
                let mut lanes = [f64x4::ZERO; R];
                for ((((lane, a), b), c), d) in lanes.iter_mut().zip(s0).zip(s1).zip(s2).zip(s3) {
                    *lane = f64x4::new([a, b, c, d]);
                }
                lanes
            }

            /// The four states of a result computed in lanes, each `R × C`.
            fn split_lanes<const R: usize, const C: usize>(value: &[[f64x4; R]; C]) -> [SMatrix<f64, R, C>; 4] {
                let mut states = [[[0.0; R]; C]; 4];
                let [s0, s1, s2, s3] = &mut states;
                for ((((column, c0), c1), c2), c3) in value.iter().zip(s0).zip(s1).zip(s2).zip(s3) {
                    for ((((x, y0), y1), y2), y3) in column.iter().zip(c0).zip(c1).zip(c2).zip(c3) {
                        [*y0, *y1, *y2, *y3] = x.to_array();
                    }
                }
                states.map(SMatrix::from)
            }
        },
        false => quote!(),
    };
    quote! {
        /// Fails the build unless `T` is `n` doubles in memory, aligned as a double.
        ///
        /// Reading and writing nalgebra's fixed-size matrices through the caller's pointers
        /// relies on it: `SMatrix<f64, R, C>` is `[[f64; R]; C]`, its columns, in memory, since
        /// `Matrix` is `repr(C)` around its storage and a zero-sized marker, and `ArrayStorage` a
        /// `repr(transparent)` array of columns. Size and alignment are held here for every
        /// shape used, the order of the entries by those two representations.
        const fn assert_doubles<T>(n: usize) {
            if size_of::<T>() != n * size_of::<f64>() || align_of::<T>() != align_of::<f64>() {
                panic!("a nalgebra matrix is not its doubles in memory");
            }
        }

        /// One state's input of `L` doubles: the caller's memory itself where it is aligned as a
        /// double is (always, from C), else a copy in `copy`. In place, the generated code's
        /// wide loads read what the caller stored (a copy stored in pieces stalls them).
        ///
        /// # Safety
        /// `p` points to `L` readable doubles, not written while the result is used.
        #[inline(always)]
        unsafe fn input<const L: usize>(p: *const f64, copy: &mut MaybeUninit<SVector<f64, L>>) -> &SVector<f64, L> {
            const { assert_doubles::<SVector<f64, L>>(L) };
            let p = p.cast::<SVector<f64, L>>();
            __dyngen_comment!("SAFETY: `L` doubles by the caller's contract, which `SVector<f64, L>` is (`assert_doubles`), read in place only where aligned.");
            match p.is_aligned() {
                true => unsafe { &*p },
                false => copy.write(unsafe { p.read_unaligned() }),
            }
        }

        /// One state's output, an `R × C` matrix (a vector: one column) column by column.
        ///
        /// # Safety
        /// `p` points to `R · C` writable doubles (no alignment needed).
        #[inline(always)]
        unsafe fn output<const R: usize, const C: usize>(p: *mut f64, value: SMatrix<f64, R, C>) {
            const { assert_doubles::<SMatrix<f64, R, C>>(R * C) };
            __dyngen_comment!("SAFETY: passed on from the caller; written unaligned, as `R · C` doubles (`assert_doubles`).");
            unsafe { p.cast::<SMatrix<f64, R, C>>().write_unaligned(value) }
        }

        /// The `k`-th pointer of a caller's array of pointers.
        ///
        /// # Safety
        /// `pointers` points to more than `k` pointers.
        #[inline(always)]
        unsafe fn nth<P>(pointers: *const P, k: usize) -> P {
            __dyngen_comment!("SAFETY: passed on from the caller.");
            unsafe { pointers.add(k).read_unaligned() }
        }

        #trig
        #lanes
    }
}

/// The robot's sizes, names, limits and parameters.
fn metadata(library: &Library) -> TokenStream {
    let prefix = &library.prefix;
    let f = |name: &str| format_ident!("{prefix}_{name}");
    let names = |list: &[String]| -> (Literal, Vec<TokenStream>) {
        (usize(list.len()), list.iter().map(|n| c_string(n)).collect())
    };
    let (joint_count, joint_names) = names(&library.joint_names);
    let (parameter_count, parameter_names) = names(&library.parameter_names);
    let (base_count, base_names) = names(&library.base_parameter_names);
    let (frame_count, frame_names) = names(&library.frame_names);
    let ty = format_ident!("{}", library.type_name);
    let [abi_version, robot_name, is_floating_base, dof, nq, nv, parameter_count_fn] = [
        "abi_version",
        "robot_name",
        "is_floating_base",
        "dof",
        "nq",
        "nv",
        "parameter_count",
    ]
    .map(f);
    let [base_parameter_count, frame_count_fn, function_count, joint_name, parameter_name] = [
        "base_parameter_count",
        "frame_count",
        "function_count",
        "joint_name",
        "parameter_name",
    ]
    .map(f);
    let [base_parameter_name, frame_name, status_message, parameters, base_parameters, joint_limits] = [
        "base_parameter_name",
        "frame_name",
        "status_message",
        "parameters",
        "base_parameters",
        "joint_limits",
    ]
    .map(f);
    let robot = c_string(&library.robot_name);
    let floating = i32::from(library.sizes.floating);
    let function_total = usize(library.entries.len());
    let base_parameters_body = match library.has_base_parameters {
        true => quote! {
            if parameters.is_null() || base_parameters.is_null() {
                return NULL_POINTER;
            }
            let mut copy = MaybeUninit::uninit();
            __dyngen_comment!("SAFETY: non-null, and `PARAMETER_COUNT` doubles by this function's contract.");
            let theta = unsafe { input::<PARAMETER_COUNT>(parameters, &mut copy) };
            let theta_b = robot::#ty::base_parameters(theta);
            __dyngen_comment!("SAFETY: non-null, and `BASE_PARAMETER_COUNT` doubles by this function's contract.");
            unsafe { output(base_parameters, theta_b) };
            OK
        },
        false => quote! {
            let _ = (parameters, base_parameters);
            NOT_GENERATED
        },
    };
    quote! {
        static JOINT_NAMES: [&u8; #joint_count] = [#(#joint_names),*];
        static PARAMETER_NAMES: [&u8; #parameter_count] = [#(#parameter_names),*];
        static BASE_PARAMETER_NAMES: [&u8; #base_count] = [#(#base_names),*];
        static FRAME_NAMES: [&u8; #frame_count] = [#(#frame_names),*];
        const _: () = assert!(JOINT_NAMES.len() == DOF && PARAMETER_NAMES.len() == PARAMETER_COUNT);
        const _: () = assert!(BASE_PARAMETER_NAMES.len() == BASE_PARAMETER_COUNT);

        /// `DYNGEN_ABI_VERSION` of the library.
        #[no_mangle]
        pub extern "C" fn #abi_version() -> u32 {
            1
        }

        /// The description's name.
        #[no_mangle]
        pub extern "C" fn #robot_name() -> &'static u8 {
            #robot
        }

        /// 1 on a floating base, else 0.
        #[no_mangle]
        pub extern "C" fn #is_floating_base() -> i32 {
            #floating
        }

        /// Moving joints (coordinates).
        #[no_mangle]
        pub extern "C" fn #dof() -> usize {
            DOF
        }

        /// Length of the configuration.
        #[no_mangle]
        pub extern "C" fn #nq() -> usize {
            NQ
        }

        /// Length of velocities and generalised forces.
        #[no_mangle]
        pub extern "C" fn #nv() -> usize {
            NV
        }

        /// Standard parameters.
        #[no_mangle]
        pub extern "C" fn #parameter_count_fn() -> usize {
            PARAMETER_COUNT
        }

        /// Base parameters.
        #[no_mangle]
        pub extern "C" fn #base_parameter_count() -> usize {
            BASE_PARAMETER_COUNT
        }

        /// Named frames, the end-effector first.
        #[no_mangle]
        pub extern "C" fn #frame_count_fn() -> usize {
            FRAME_NAMES.len()
        }

        /// Entries of the function table.
        #[no_mangle]
        pub extern "C" fn #function_count() -> usize {
            #function_total
        }

        /// Joint `joint`'s name, NUL-terminated; null when out of range.
        #[no_mangle]
        pub extern "C" fn #joint_name(joint: usize) -> Option<&'static u8> {
            JOINT_NAMES.get(joint).copied()
        }

        /// Standard parameter `parameter`'s name; null when out of range.
        #[no_mangle]
        pub extern "C" fn #parameter_name(parameter: usize) -> Option<&'static u8> {
            PARAMETER_NAMES.get(parameter).copied()
        }

        /// Base parameter `base_parameter`'s name (what it combines); null when out of range.
        #[no_mangle]
        pub extern "C" fn #base_parameter_name(base_parameter: usize) -> Option<&'static u8> {
            BASE_PARAMETER_NAMES.get(base_parameter).copied()
        }

        /// Frame `frame`'s name; null when out of range.
        #[no_mangle]
        pub extern "C" fn #frame_name(frame: usize) -> Option<&'static u8> {
            FRAME_NAMES.get(frame).copied()
        }

        /// What a status code means.
        #[no_mangle]
        pub extern "C" fn #status_message(status: i32) -> &'static u8 {
            match status {
                OK => &b"success\0"[0],
                NULL_POINTER => &b"a pointer argument is null\0"[0],
                NON_UNIT_QUATERNION => &b"the base quaternion (q[3..7], x y z w) is not a unit quaternion (tolerance 1e-6)\0"[0],
                FRAME_OUT_OF_RANGE => &b"the frame index is not below the number of frames\0"[0],
                FUNCTION_OUT_OF_RANGE => &b"the function index is not below the number of functions\0"[0],
                NOT_GENERATED => &b"the robot was generated without this function\0"[0],
                CONTACT_SETTINGS => &b"a contact solve's setting is out of range: mu or damping negative or not finite, no iteration, a gain not finite, or a restitution outside [0, 1]\0"[0],
                REDUNDANT_CONTACTS => &b"the contact rows are redundant at this configuration (a row depends on the others): solve with mu > 0\0"[0],
                _ => &b"unknown status\0"[0],
            }
        }

        /// The standard parameters θ of the description.
        ///
        /// # Safety
        /// `parameters` points to `PARAMETER_COUNT` writable doubles.
        #[no_mangle]
        pub unsafe extern "C" fn #parameters(parameters: *mut f64) -> i32 {
            if parameters.is_null() {
                return NULL_POINTER;
            }
            __dyngen_comment!("SAFETY: non-null, and `PARAMETER_COUNT` doubles by this function's contract.");
            unsafe { output(parameters, robot::#ty::parameters()) };
            OK
        }

        /// The base parameters `θ_b = Φ θ` of any standard parameters.
        ///
        /// # Safety
        /// `parameters` points to `PARAMETER_COUNT` readable doubles, `base_parameters` to
        /// `BASE_PARAMETER_COUNT` writable ones.
        #[no_mangle]
        pub unsafe extern "C" fn #base_parameters(parameters: *const f64, base_parameters: *mut f64) -> i32 {
            #base_parameters_body
        }

        /// The joint limits of the description (infinite where it sets none).
        ///
        /// # Safety
        /// Each pointer points to `DOF` writable doubles.
        #[no_mangle]
        pub unsafe extern "C" fn #joint_limits(lower: *mut f64, upper: *mut f64, velocity: *mut f64, effort: *mut f64) -> i32 {
            if lower.is_null() || upper.is_null() || velocity.is_null() || effort.is_null() {
                return NULL_POINTER;
            }
            let limits = robot::JOINT_LIMITS;
            let column = |f: fn(&dyngen_runtime::JointLimits) -> f64| SVector::from(limits.map(|l| f(&l)));
            __dyngen_comment!("SAFETY: non-null, and `DOF` doubles each by this function's contract.");
            unsafe {
                output(lower, column(|l| l.lower));
                output(upper, column(|l| l.upper));
                output(velocity, column(|l| l.velocity));
                output(effort, column(|l| l.effort));
            }
            OK
        }
    }
}

/// The static table `P_function_info` returns.
fn table(library: &Library) -> TokenStream {
    let info = format_ident!("{}_function_info", library.prefix);
    let arrays = |list: &[Array]| -> Vec<TokenStream> {
        list.iter()
            .map(|a| {
                let (name, rows, cols) = (c_string(a.name), usize(a.rows), usize(a.cols));
                quote!(Array { name: #name, rows: #rows, cols: #cols })
            })
            .collect()
    };
    let mut statics = Vec::new();
    let mut rows = Vec::new();
    for (index, entry) in library.entries.iter().enumerate() {
        let (inputs, outputs) = (format_ident!("INPUTS_{index}"), format_ident!("OUTPUTS_{index}"));
        let (input_arrays, output_arrays) = (arrays(&entry.inputs), arrays(&entry.outputs));
        let (input_count, output_count) = (usize(entry.inputs.len()), usize(entry.outputs.len()));
        statics.push(quote! {
            static #inputs: [Array; #input_count] = [#(#input_arrays),*];
            static #outputs: [Array; #output_count] = [#(#output_arrays),*];
        });
        let (name, quantity) = (c_string(&entry.name()), c_string(entry.kind.name()));
        let lanes = usize(entry.lanes);
        let takes_frame = i32::from(entry.takes_frame());
        let reference = reference_number(entry.reference);
        rows.push(quote! {
            FunctionInfo {
                name: #name,
                quantity: #quantity,
                input_count: #input_count,
                inputs: &#inputs[0],
                output_count: #output_count,
                outputs: &#outputs[0],
                lanes: #lanes,
                takes_frame: #takes_frame,
                reference_frame: #reference,
            }
        });
    }
    let count = usize(rows.len());
    quote! {
        /// `dyngen_array`: one input or output of one state.
        #[repr(C)]
        pub struct Array {
            pub name: &'static u8,
            pub rows: usize,
            pub cols: usize,
        }

        /// `dyngen_function_info`: one entry of the table.
        #[repr(C)]
        pub struct FunctionInfo {
            pub name: &'static u8,
            pub quantity: &'static u8,
            pub input_count: usize,
            pub inputs: &'static Array,
            pub output_count: usize,
            pub outputs: &'static Array,
            pub lanes: usize,
            pub takes_frame: i32,
            pub reference_frame: i32,
        }

        #(#statics)*

        static FUNCTIONS: [FunctionInfo; #count] = [#(#rows),*];

        /// Entry `function` of the table; null when out of range.
        #[no_mangle]
        pub extern "C" fn #info(function: usize) -> Option<&'static FunctionInfo> {
            FUNCTIONS.get(function)
        }
    }
}

/// The spellings one entry's functions share.
struct Spelled {
    state: proc_macro2::Ident,
    batch: proc_macro2::Ident,
    /// Input and output pointers, named as the table names them.
    inputs: Vec<proc_macro2::Ident>,
    outputs: Vec<proc_macro2::Ident>,
    input_lengths: Vec<Literal>,
    output_lengths: Vec<Literal>,
}

fn spelled(index: usize, entry: &Entry) -> Spelled {
    Spelled {
        state: format_ident!("state_{index}"),
        batch: format_ident!("batch_{index}"),
        inputs: entry.inputs.iter().map(|a| format_ident!("{}", a.name)).collect(),
        outputs: entry
            .outputs
            .iter()
            .map(|a| format_ident!("{}", a.name))
            .collect(),
        input_lengths: entry.inputs.iter().map(|a| usize(a.len())).collect(),
        output_lengths: entry.outputs.iter().map(|a| usize(a.len())).collect(),
    }
}

/// The frame argument of a frame quantity's state function and its lookup.
fn frame_lookup(entry: &Entry) -> (TokenStream, TokenStream) {
    match entry.takes_frame() {
        true => (
            quote!(frame,),
            quote! {
                let Some(&frame) = <robot::Frame as RobotFrame>::ALL.get(frame) else {
                    return FRAME_OUT_OF_RANGE;
                };
            },
        ),
        false => (quote!(), quote!(let _ = frame;)),
    }
}

/// Every entry's state function, exported function and batch loop.
fn functions(library: &Library) -> TokenStream {
    (library.entries.iter().enumerate())
        .map(|(index, entry)| {
            let s = spelled(index, entry);
            [
                state_function(library, entry, &s),
                exported_function(library, entry, &s),
                batch_function(library, entry, &s),
            ]
            .into_iter()
            .collect::<TokenStream>()
        })
        .collect()
}

/// `unsafe fn state_K([frame,] inputs…, outputs…) -> i32`: one state, read in place, the
/// results written straight from the generated function's values.
fn state_function(library: &Library, entry: &Entry, s: &Spelled) -> TokenStream {
    let ty = format_ident!("{}", library.type_name);
    let method = format_ident!("{}", entry.kind.name());
    let (state, inputs, outputs, lengths) = (&s.state, &s.inputs, &s.outputs, &s.input_lengths);
    let (frame_parameter, frame_argument) = match entry.takes_frame() {
        true => (quote!(frame: robot::Frame,), quote!(frame,)),
        false => (quote!(), quote!()),
    };
    let reference = match entry.reference {
        Some(r) => {
            let variant = format_ident!("{r:?}");
            quote!(ReferenceFrame::#variant,)
        }
        None => quote!(),
    };
    let copies: Vec<_> = (0..inputs.len()).map(|k| format_ident!("copy{k}")).collect();
    let args = inputs.iter().skip(1);
    // The generated function's result, part by part, in the order of the outputs.
    let parts = match entry.shape {
        Shape::Vector(_) | Shape::Matrix(..) => vec![quote!(value)],
        Shape::Pose => vec![quote!(value.rotation), quote!(value.translation)],
        Shape::MatrixPair(..) | Shape::VectorPair(..) => vec![quote!(value.0), quote!(value.1)],
        Shape::Kinematics(_) => vec![
            quote!(value.0.rotation),
            quote!(value.0.translation),
            quote!(value.1),
            quote!(value.2),
        ],
        Shape::ContactMatrices(..) => vec![
            quote!(value.jacobian),
            quote!(value.response),
            quote!(value.delassus),
        ],
        Shape::ContactSystem(..) => vec![
            quote!(value.matrices.jacobian),
            quote!(value.matrices.response),
            quote!(value.matrices.delassus),
            quote!(value.drift),
            quote!(value.free_acceleration),
        ],
        Shape::ContactStep(..) => vec![
            quote!(value.acceleration),
            quote!(value.forces),
            quote!(value.previous_forces),
            quote!(value.delassus),
            quote!(value.pivots),
            quote!(value.rhs),
        ],
        Shape::ContactInertia(..) => vec![
            quote!(value.inertia),
            quote!(value.pivots),
            quote!(value.delassus_diagonal),
        ],
    };
    let doc = format!(" `{}` of one state.", entry.name());
    let safety = pointer_contract(entry, "");
    quote! {
        #[doc = #doc]
        ///
        /// # Safety
        #[doc = #safety]
        #[inline(always)]
        unsafe fn #state(#frame_parameter #(#inputs: *const f64,)* #(#outputs: *mut f64),*) -> i32 {
            #(let mut #copies = MaybeUninit::uninit();)*
            __dyngen_comment!("SAFETY: each input holds its length in doubles (the contract).");
            let (#(#inputs,)*) = unsafe { (#(input::<#lengths>(#inputs, &mut #copies),)*) };
            let t = match trig(q) {
                Ok(t) => t,
                Err(status) => return status,
            };
            let value = robot::#ty::#method(#frame_argument #reference &t, #(#args),*);
            __dyngen_comment!("SAFETY: each output holds its rows × cols doubles (the contract).");
            unsafe { #(output(#outputs, #parts);)* }
            OK
        }
    }
}

/// The `# Safety` of a function whose inputs and outputs are `entry`'s, for `states` states.
fn pointer_contract(entry: &Entry, states: &str) -> String {
    let arrays = |list: &[Array], access: &str| -> Vec<String> {
        list.iter()
            .map(|a| format!("`{}` to {states}{} {access} doubles", a.name, a.len()))
            .collect()
    };
    let mut parts = arrays(&entry.inputs, "readable");
    parts.extend(arrays(&entry.outputs, "writable"));
    format!(
        " Each pointer, non-null, points to the doubles its array holds: {}. Outputs must not \
         overlap each other (inputs are read before any output is written).",
        parts.join(", ")
    )
}

/// `P_<name>([frame,] inputs…, outputs…)`: the exported function of one state.
fn exported_function(library: &Library, entry: &Entry, s: &Spelled) -> TokenStream {
    let name = format_ident!("{}_{}", library.prefix, entry.name());
    let (state, inputs, outputs) = (&s.state, &s.inputs, &s.outputs);
    let (frame_argument, lookup) = frame_lookup(entry);
    let (frame_parameter, lookup) = match entry.takes_frame() {
        true => (quote!(frame: usize,), lookup),
        false => (quote!(), quote!()),
    };
    let summary = format!(" {}.", first_upper(entry.kind.summary()));
    let safety = pointer_contract(entry, "");
    quote! {
        #[doc = #summary]
        ///
        /// # Safety
        #[doc = #safety]
        #[no_mangle]
        pub unsafe extern "C" fn #name(#frame_parameter #(#inputs: *const f64,)* #(#outputs: *mut f64),*) -> i32 {
            if #(#inputs.is_null())||* || #(#outputs.is_null())||* {
                return NULL_POINTER;
            }
            #lookup
            __dyngen_comment!("SAFETY: non-null, and the lengths of this function's contract.");
            unsafe { #state(#frame_argument #(#inputs,)* #(#outputs),*) }
        }
    }
}

/// `batch_K(frame, batch, inputs, outputs)`: `P_evaluate` of one entry, in lanes where the
/// robot has them.
fn batch_function(library: &Library, entry: &Entry, s: &Spelled) -> TokenStream {
    let (batch_fn, state, inputs, outputs) = (&s.batch, &s.state, &s.inputs, &s.outputs);
    let (input_lengths, output_lengths) = (&s.input_lengths, &s.output_lengths);
    let (input_index, output_index) = (
        (0..inputs.len()).map(usize).collect::<Vec<_>>(),
        (0..outputs.len()).map(usize).collect::<Vec<_>>(),
    );
    let (frame_argument, lookup) = frame_lookup(entry);
    let check = match library.sizes.floating {
        true => quote! {
            __dyngen_comment!("SAFETY: `q` holds `batch` configurations (the contract).");
            if let Err(status) = unsafe { check_configurations(q, batch) } {
                return status;
            }
        },
        false => quote!(),
    };
    let lanes = match entry.lanes > 1 {
        true => lane_loop(library, entry, s),
        false => quote!(),
    };
    let safety = pointer_contract(entry, "`batch` × ");
    quote! {
        /// # Safety
        /// `inputs` and `outputs` point to one pointer per input and output of the entry.
        #[doc = #safety]
        unsafe fn #batch_fn(frame: usize, batch: usize, inputs: *const *const f64, outputs: *const *mut f64) -> i32 {
            if inputs.is_null() || outputs.is_null() {
                return NULL_POINTER;
            }
            __dyngen_comment!("SAFETY: one pointer per input and output (the contract).");
            let (#(#inputs,)*) = unsafe { (#(nth(inputs, #input_index),)*) };
            let (#(#outputs,)*) = unsafe { (#(nth(outputs, #output_index),)*) };
            if #(#inputs.is_null())||* || #(#outputs.is_null())||* {
                return NULL_POINTER;
            }
            #lookup
            #check
            let mut s = 0;
            #lanes
            while s < batch {
                __dyngen_comment!("SAFETY: state `s` of every array lies within its `batch` states.");
                let status = unsafe {
                    #state(#frame_argument #(#inputs.add(#input_lengths * s),)* #(#outputs.add(#output_lengths * s)),*)
                };
                if status != OK {
                    return status;
                }
                s += 1;
            }
            OK
        }
    }
}

/// The loop of a batch that computes four states per call of the lane form.
fn lane_loop(library: &Library, entry: &Entry, s: &Spelled) -> TokenStream {
    let ty = format_ident!("{}", library.type_name);
    let method = format_ident!("{}_lanes", entry.kind.name());
    let (inputs, outputs, lengths) = (&s.inputs, &s.outputs, &s.input_lengths);
    let output_lengths = &s.output_lengths;
    let args = inputs.iter().skip(1);
    // A vector comes back as `[L; N]`, a matrix as `[[L; N]; C]`: both as columns.
    let columns = match entry.shape {
        Shape::Vector(_) => quote!(&[value]),
        _ => quote!(&value),
    };
    debug_assert!(entry.args.iter().all(|a| matches!(a, Arg::Qd | Arg::A)));
    debug_assert_eq!(outputs.len(), 1);
    quote! {
        while batch - s >= 4 {
            __dyngen_comment!("SAFETY: states `s` to `s + 3` of every array lie within its `batch` states.");
            let (#(#inputs,)*) = unsafe { (#(read_lanes::<#lengths>(#inputs.add(#lengths * s)),)*) };
            let t = JointTrigLanes::new(&q);
            let value = robot::#ty::#method(&t, #(&#args),*);
            for (k, state) in split_lanes(#columns).into_iter().enumerate() {
                __dyngen_comment!("SAFETY: as for the inputs.");
                unsafe { #(output(#outputs.add(#output_lengths * (s + k)), state);)* }
            }
            s += 4;
        }
    }
}

/// `P_evaluate`: the batch of any entry.
fn evaluate(library: &Library) -> TokenStream {
    let name = format_ident!("{}_evaluate", library.prefix);
    let arms = (0..library.entries.len()).map(|index| {
        let (k, batch) = (usize(index), format_ident!("batch_{index}"));
        quote!(#k => unsafe { #batch(frame, batch, inputs, outputs) })
    });
    quote! {
        /// Entry `function` of the table on `batch` states: input `k` holds `batch` states of
        /// its length, output `k` `batch` blocks of its rows × cols, column-major.
        ///
        /// # Safety
        /// `inputs` and `outputs` point to one pointer per input and output of the entry (its
        /// `dyngen_function_info`), each to `batch` states of that array.
        #[no_mangle]
        pub unsafe extern "C" fn #name(
            function: usize,
            frame: usize,
            batch: usize,
            inputs: *const *const f64,
            outputs: *const *mut f64,
        ) -> i32 {
            __dyngen_comment!("SAFETY: the contract, passed on to the entry's batch.");
            match function {
                #(#arms,)*
                _ => FUNCTION_OUT_OF_RANGE,
            }
        }
    }
}

/// `text` with its first letter in upper case.
pub(super) fn first_upper(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(c) => c.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}
