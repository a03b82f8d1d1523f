//! The C headers: `dyngen.h`, the types and codes every robot's library shares, and
//! `<prefix>_dynamics.h`, the robot's sizes, names and one documented declaration per entry of
//! its table.

use super::table::{reference_number, Array, Entry, Size};
use super::wrapper::first_upper;
use super::Library;
use crate::generate::GENERATED_MARKER;
use std::fmt::Write as _;

/// The version of the C interface a library is generated for (`DYNGEN_ABI_VERSION`).
pub(super) const ABI_VERSION: u32 = 1;

/// `dyngen.h`: the same text for every robot, guarded by the ABI version so that two robots'
/// copies can both be included.
pub(super) fn shared_header() -> String {
    format!(
        r#"{GENERATED_MARKER}
// dyngen.h: what every C library dyngen generates shares: status codes, reference frames and
// the types of the function table (docs/c-library.md in dyngen's repository).
// Do not edit by hand: every generated robot library carries this same file.
#ifndef DYNGEN_H_ABI_{ABI_VERSION}
#define DYNGEN_H_ABI_{ABI_VERSION}

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {{
#endif

/* The version of this interface; a library reports its own with P_abi_version(). */
#define DYNGEN_ABI_VERSION {ABI_VERSION}

/* Status codes: the return value of every function that computes. On an error, nothing is
 * written. When several errors apply, the first in this order is reported. */
#define DYNGEN_OK 0
/* A pointer argument, or a pointer in the inputs or outputs array of P_evaluate, is NULL. */
#define DYNGEN_ERROR_NULL_POINTER 1
/* Floating base: the quaternion q[3..7] (x y z w) is not of unit norm within 1e-6 (or NaN). */
#define DYNGEN_ERROR_NON_UNIT_QUATERNION 2
/* The frame index is not below P_frame_count(). */
#define DYNGEN_ERROR_FRAME_OUT_OF_RANGE 3
/* P_evaluate: the function index is not below P_function_count(). */
#define DYNGEN_ERROR_FUNCTION_OUT_OF_RANGE 4
/* P_base_parameters of a robot generated without base parameters. */
#define DYNGEN_ERROR_NOT_GENERATED 5

/* The reference frame of a frame quantity (Pinocchio's ReferenceFrame). */
#define DYNGEN_NO_REFERENCE_FRAME (-1)
/* The frame's own axes, at its origin: the body velocity. */
#define DYNGEN_LOCAL 0
/* Base axes, at the base origin: the spatial velocity. */
#define DYNGEN_WORLD 1
/* Base axes, at the frame's origin: the linear part is the velocity of the frame's origin. */
#define DYNGEN_LOCAL_WORLD_ALIGNED 2

/* One input (rows x 1) or output (rows x cols, column-major) of one state. */
typedef struct dyngen_array {{
    const char *name;
    size_t rows;
    size_t cols;
}} dyngen_array;

/* One entry of a robot's function table: static data, valid while the library is loaded. */
typedef struct dyngen_function_info {{
    /* The C function is P_<name>, e.g. "frame_jacobian_local". */
    const char *name;
    /* The generated quantity, e.g. "frame_jacobian". */
    const char *quantity;
    size_t input_count;
    /* "q" first, then the other inputs in the order the function takes them. */
    const dyngen_array *inputs;
    size_t output_count;
    /* In the order the function takes them. */
    const dyngen_array *outputs;
    /* States P_evaluate computes per call: 1, or 4 (SIMD lanes). */
    size_t lanes;
    /* 1: takes a frame index (the first argument of P_<name>, and P_evaluate's frame). */
    int32_t takes_frame;
    /* DYNGEN_LOCAL, DYNGEN_WORLD, DYNGEN_LOCAL_WORLD_ALIGNED or DYNGEN_NO_REFERENCE_FRAME. */
    int32_t reference_frame;
}} dyngen_function_info;

#ifdef __cplusplus
}}
#endif

#endif
"#
    )
}

/// An identifier in upper case, for macros.
fn upper(name: &str) -> String {
    name.to_ascii_uppercase()
}

/// How the header spells a size of `library`.
fn size(library: &Library, size: Size) -> String {
    let macro_prefix = upper(&library.prefix);
    match size {
        Size::Nq => format!("{macro_prefix}_NQ"),
        Size::Nv => format!("{macro_prefix}_NV"),
        Size::Parameters => format!("{macro_prefix}_PARAMETER_COUNT"),
        Size::BaseParameters => format!("{macro_prefix}_BASE_PARAMETER_COUNT"),
        Size::Number(n) => n.to_string(),
    }
}

/// `PANDA_NV` or `PANDA_NV x PANDA_NV`.
fn shape(library: &Library, array: &Array) -> String {
    match array.spelled {
        [rows, Size::Number(1)] => size(library, rows),
        [rows, cols] => format!("{} x {}", size(library, rows), size(library, cols)),
    }
}

/// `<prefix>_dynamics.h`.
pub(super) fn robot_header(library: &Library) -> String {
    let p = &library.prefix;
    let pp = upper(p);
    let s = &library.sizes;
    let mut h = format!(
        "{GENERATED_MARKER}\n\
         // {name}: the C interface of the rigid-body dynamics of `{robot}` ({about}), generated\n\
         // by dyngen {version} from `{source}`. Every symbol starts with `{p}_`.\n\
         // Do not edit by hand: regenerate with `{regenerate}`.\n\
         //\n\
         // Conventions (docs/c-library.md in dyngen's repository):\n\
         // - Arrays are flat doubles; matrices column-major (entry (i, j) of an r x c matrix at\n\
         //   i + r*j), as Eigen stores them by default.\n\
         // - SI units: m, rad, s, kg; torques N*m (angles) or N (lengths); six-vectors are\n\
         //   [linear; angular] velocities and [force; moment] wrenches.\n\
         // - {layout}\n\
         // - Every function that computes returns DYNGEN_OK or an error code of dyngen.h and,\n\
         //   on error, writes nothing. None allocates, keeps state between calls or unwinds: any\n\
         //   function may be called from any thread, a real-time loop included.\n\
         // - Pointers: each is non-null (else DYNGEN_ERROR_NULL_POINTER) and points to as many\n\
         //   doubles as its array holds (no alignment needed); a shorter array is undefined\n\
         //   behaviour. Inputs are read before outputs are written; outputs must not overlap.\n\
         #ifndef {pp}_DYNAMICS_H\n\
         #define {pp}_DYNAMICS_H\n\n\
         #include \"dyngen.h\"\n\n\
         #ifdef __cplusplus\n\
         extern \"C\" {{\n\
         #endif\n\n",
        name = library.header_name(),
        robot = library.robot_name,
        about = library.sizes_summary,
        version = env!("CARGO_PKG_VERSION"),
        source = library.source,
        regenerate = library.regenerate,
        layout = match s.floating {
            true => format!(
                "Floating base: q = [x, y, z, qx, qy, qz, qw, joints] ({pp}_NQ = dof + 7, a unit\n\
                 //   quaternion); velocities (qd, v, a, qdd) are nu = [v; w; joint rates] with the\n\
                 //   base twist in the base frame ({pp}_NV = dof + 6); forces start with the base wrench."
            ),
            false =>
                format!("Fixed base: q and every velocity and force have one entry per joint ({pp}_DOF)."),
        }
    );
    let sizes = [
        ("DOF", s.dof, "moving joints (coordinates)"),
        ("NQ", s.nq, "length of the configuration q"),
        ("NV", s.nv, "length of velocities, accelerations and forces"),
        ("PARAMETER_COUNT", s.parameters, "standard parameters θ"),
        ("BASE_PARAMETER_COUNT", s.base_parameters, "base parameters θ_b"),
        ("FRAME_COUNT", s.frames, "named frames, the end-effector first"),
        (
            "FUNCTION_COUNT",
            library.entries.len(),
            "entries of the function table",
        ),
    ];
    h += "/* Sizes. */\n";
    for (name, value, about) in sizes {
        let _ = writeln!(h, "#define {pp}_{name} {value} /* {about} */");
    }
    let _ = write!(
        h,
        "\n/* The same sizes as values. */\n\
         typedef struct {p}_sizes_t {{\n    size_t dof, nq, nv, parameter_count, base_parameter_count, frame_count, function_count;\n}} {p}_sizes_t;\n\
         static const {p}_sizes_t {p}_sizes = {{{}}};\n",
        sizes.map(|(name, ..)| format!("{pp}_{name}")).join(", ")
    );
    h += "\n/* Frame indices (the frame argument of frame functions). */\n";
    for (index, (name, spelled)) in library
        .frame_names
        .iter()
        .zip(&library.frame_spellings)
        .enumerate()
    {
        let _ = writeln!(
            h,
            "#define {pp}_FRAME_{} {index} /* \"{}\" */",
            upper(spelled),
            c_comment(name)
        );
    }
    h += "\n/* Function indices (the function argument of P_evaluate and P_function_info). */\n";
    for (index, entry) in library.entries.iter().enumerate() {
        let _ = writeln!(h, "#define {pp}_FUNCTION_{} {index}", upper(&entry.name()));
    }
    h += &robot_functions(library);
    for entry in &library.entries {
        h += &declaration(library, entry);
    }
    h += "\n#ifdef __cplusplus\n}\n#endif\n\n#endif\n";
    h
}

/// Text safe inside a C comment.
fn c_comment(text: &str) -> String {
    text.replace("*/", "* /").replace('\n', " ")
}

/// The robot's functions besides the table's.
fn robot_functions(library: &Library) -> String {
    let p = &library.prefix;
    let pp = upper(p);
    format!(
        r#"
/* The robot. */

/* DYNGEN_ABI_VERSION of the library: check it against dyngen.h's when loading it at run time. */
uint32_t {p}_abi_version(void);
/* The description's name, NUL-terminated UTF-8 (static). */
const char *{p}_robot_name(void);
/* 1 on a floating base, else 0. */
int32_t {p}_is_floating_base(void);
/* {pp}_DOF, {pp}_NQ, {pp}_NV, {pp}_PARAMETER_COUNT, {pp}_BASE_PARAMETER_COUNT, {pp}_FRAME_COUNT and
 * {pp}_FUNCTION_COUNT, for code that loads the library without this header. */
size_t {p}_dof(void);
size_t {p}_nq(void);
size_t {p}_nv(void);
size_t {p}_parameter_count(void);
size_t {p}_base_parameter_count(void);
size_t {p}_frame_count(void);
size_t {p}_function_count(void);
/* Names, NUL-terminated UTF-8 (static); NULL when the index is out of range. Joints in the
 * order of q; parameters as "m[link]", "mcx[link]", …; base parameters as what they combine;
 * frames in the order of the frame indices. */
const char *{p}_joint_name(size_t joint);
const char *{p}_parameter_name(size_t parameter);
const char *{p}_base_parameter_name(size_t base_parameter);
const char *{p}_frame_name(size_t frame);
/* A sentence for a status code (static; unknown codes too). */
const char *{p}_status_message(int32_t status);
/* The standard parameters θ of the description into parameters[{pp}_PARAMETER_COUNT]: ten per
 * body [m, m*cx, m*cy, m*cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz] about its joint frame's origin (kg,
 * kg*m, kg*m^2), the base body's first on a floating base, then the joint-level ones. */
int32_t {p}_parameters(double *parameters);
/* The base parameters θ_b = Φ θ of parameters[{pp}_PARAMETER_COUNT] into
 * base_parameters[{pp}_BASE_PARAMETER_COUNT]; DYNGEN_ERROR_NOT_GENERATED for a robot generated
 * without base parameters. */
int32_t {p}_base_parameters(const double *parameters, double *base_parameters);
/* The joint limits of the description, {pp}_DOF each: position (rad or m), speed (rad/s or
 * m/s), effort (N*m or N); infinite where the description sets none. */
int32_t {p}_joint_limits(double *lower, double *upper, double *velocity, double *effort);

/* The table, for bindings: entry `function` (NULL when out of range). */
const dyngen_function_info *{p}_function_info(size_t function);
/* Entry `function` of the table on `batch` states. inputs[k] points to batch x rows_k doubles
 * (state after state), outputs[k] to batch x rows_k x cols_k (each state's block
 * column-major). `frame` is the frame index of an entry that takes one, ignored otherwise.
 * Entries with lanes == 4 compute four states per call. On a floating base every state's
 * quaternion is checked before anything is written. Inputs and outputs must not overlap. */
int32_t {p}_evaluate(size_t function, size_t frame, size_t batch, const double *const *inputs,
                     double *const *outputs);

/* One function per entry of the table. */
"#
    )
}

/// A C comment block of `paragraphs`, each a lead (kept as it is), an indent for its
/// continuation lines and a text, wrapped between words to 100 columns.
fn comment_block(paragraphs: &[(String, usize, String)]) -> String {
    const WIDTH: usize = 100 - 3;
    let mut lines: Vec<String> = Vec::new();
    for (lead, hang, text) in paragraphs {
        let mut line = lead.clone();
        for word in text.split(' ') {
            let fits = line.chars().count() + 1 + word.chars().count() <= WIDTH;
            if !fits && line.trim().len() > lead.trim().len() {
                lines.push(std::mem::replace(&mut line, " ".repeat(*hang)));
            } else if !line.ends_with(' ') {
                line.push(' ');
            }
            line += word;
        }
        lines.push(line);
    }
    let mut block = String::new();
    for (k, line) in lines.iter().enumerate() {
        let opening = if k == 0 { "/* " } else { " * " };
        let closing = if k + 1 == lines.len() { " */" } else { "" };
        block += &format!("{opening}{line}{closing}\n");
    }
    block
}

/// One entry's declaration with its documentation.
fn declaration(library: &Library, entry: &Entry) -> String {
    let p = &library.prefix;
    let pp = upper(p);
    let name = entry.name();
    let mut paragraphs = vec![(
        format!("{p}_{name}: "),
        2,
        format!("{}.", first_upper(entry.kind.summary())),
    )];
    if let Some(reference) = entry.reference {
        let (macro_name, meaning) = match reference_number(Some(reference)) {
            0 => ("DYNGEN_LOCAL", "in the frame's own axes, at its origin"),
            1 => ("DYNGEN_WORLD", "in base axes, at the base origin"),
            _ => (
                "DYNGEN_LOCAL_WORLD_ALIGNED",
                "in base axes, at the frame's origin",
            ),
        };
        paragraphs.push(("Reference frame: ".into(), 2, format!("{macro_name}, {meaning}.")));
    }
    let width = (entry.inputs.iter().chain(&entry.outputs))
        .map(|a| a.name.len())
        .max()
        .unwrap_or(0)
        .max(5);
    let argument = |name: &str, direction: &str| format!("  {name:<width$}  {direction:<3} ");
    let hang = width + 8;
    if entry.takes_frame() {
        let about = format!("a frame index below {pp}_FRAME_COUNT ({pp}_FRAME_…)");
        paragraphs.push((argument("frame", "in"), hang, about));
    }
    for a in &entry.inputs {
        let about = format!("{} doubles: {}", shape(library, a), a.about);
        paragraphs.push((argument(a.name, "in"), hang, about));
    }
    for a in &entry.outputs {
        let mut about = format!("{} doubles", shape(library, a));
        if a.cols > 1 {
            about += ", column-major";
        }
        if !a.about.is_empty() {
            about += &format!(": {}", a.about);
        }
        paragraphs.push((argument(a.name, "out"), hang, about));
    }
    let mut errors = vec!["DYNGEN_ERROR_NULL_POINTER"];
    if entry.takes_frame() {
        errors.push("DYNGEN_ERROR_FRAME_OUT_OF_RANGE");
    }
    if library.sizes.floating {
        errors.push("DYNGEN_ERROR_NON_UNIT_QUATERNION");
    }
    paragraphs.push((
        "Returns ".into(),
        2,
        format!("DYNGEN_OK, or {}.", errors.join(", ")),
    ));
    let mut parameters: Vec<String> = Vec::new();
    if entry.takes_frame() {
        parameters.push("size_t frame".into());
    }
    parameters.extend(entry.inputs.iter().map(|a| format!("const double *{}", a.name)));
    parameters.extend(entry.outputs.iter().map(|a| format!("double *{}", a.name)));
    format!(
        "\n{}int32_t {p}_{name}({});\n",
        comment_block(&paragraphs),
        parameters.join(", ")
    )
}
