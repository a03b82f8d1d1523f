//! A C library as a binding uses it: its shared library loaded at run time and every entry
//! called through `P_evaluate` with arrays at any address. A binding passes addresses (ctypes,
//! a NumPy view at an odd offset, Rust), so an array one byte off a double's alignment must
//! give the same bits as an aligned one, in and out, one state and a batch in lanes. (C itself
//! never passes one: forming a misaligned `double *` is undefined there.)

use super::build::{run, Library};
use std::ffi::{c_char, CStr};

/// `dyngen_array`.
#[repr(C)]
struct Array {
    name: *const c_char,
    rows: usize,
    cols: usize,
}

/// `dyngen_function_info`.
#[repr(C)]
struct FunctionInfo {
    name: *const c_char,
    quantity: *const c_char,
    input_count: usize,
    inputs: *const Array,
    output_count: usize,
    outputs: *const Array,
    lanes: usize,
    takes_frame: i32,
    reference_frame: i32,
}

type Count = unsafe extern "C" fn() -> usize;
type Info = unsafe extern "C" fn(usize) -> *const FunctionInfo;
type Evaluate = unsafe extern "C" fn(usize, usize, usize, *const *const f64, *const *mut f64) -> i32;

/// One entry of a loaded library's table, copied out of its static data.
struct Entry {
    name: String,
    /// Input names and lengths; output lengths (doubles per state).
    inputs: Vec<(String, usize)>,
    outputs: Vec<usize>,
    takes_frame: bool,
}

/// `library`'s table, read through its `P_function_count` and `P_function_info`.
fn table(shared: &libloading::Library, prefix: &str) -> Vec<Entry> {
    // SAFETY: the symbols have the types of dyngen.h; the table is static data, valid while
    // the library is loaded, its arrays `input_count` and `output_count` long.
    unsafe {
        let count = *shared
            .get::<Count>(format!("{prefix}_function_count").as_bytes())
            .expect("count");
        let info = *shared
            .get::<Info>(format!("{prefix}_function_info").as_bytes())
            .expect("info");
        (0..count())
            .map(|f| {
                let info = &*info(f);
                let arrays = |p: *const Array, n: usize| std::slice::from_raw_parts(p, n);
                let name = |p: *const c_char| CStr::from_ptr(p).to_string_lossy().into_owned();
                Entry {
                    name: name(info.name),
                    inputs: (arrays(info.inputs, info.input_count).iter())
                        .map(|a| (name(a.name), a.rows * a.cols))
                        .collect(),
                    outputs: (arrays(info.outputs, info.output_count).iter())
                        .map(|a| a.rows * a.cols)
                        .collect(),
                    takes_frame: info.takes_frame == 1,
                }
            })
            .collect()
    }
}

/// Doubles one byte past a double's alignment, kept as bytes.
struct Shifted {
    bytes: Vec<u8>,
    offset: usize,
    len: usize,
}

impl Shifted {
    fn new(values: &[f64]) -> Shifted {
        let bytes = vec![0; 8 * values.len() + 8];
        // The offset that puts the first double at an address ≡ 1 (mod 8).
        let offset = (9 - bytes.as_ptr() as usize % 8) % 8;
        let mut shifted = Shifted {
            bytes,
            offset,
            len: values.len(),
        };
        for (chunk, v) in shifted.span().chunks_exact_mut(8).zip(values) {
            chunk.copy_from_slice(&v.to_ne_bytes());
        }
        shifted
    }

    fn span(&mut self) -> &mut [u8] {
        &mut self.bytes[self.offset..self.offset + 8 * self.len]
    }

    fn pointer(&mut self) -> *mut f64 {
        let pointer = self.span().as_mut_ptr().cast::<f64>();
        assert_eq!(pointer as usize % 8, 1);
        pointer
    }

    fn bits(&mut self) -> Vec<u64> {
        (self.span().chunks_exact(8))
            .map(|c| u64::from_ne_bytes(c.try_into().expect("eight bytes")))
            .collect()
    }
}

/// Entry `f` on the first `batch` states, from aligned arrays and from shifted ones: the
/// outputs' bits, each way.
fn both_ways(
    evaluate: Evaluate,
    library: &Library,
    (f, entry): (usize, &Entry),
    frame: usize,
    batch: usize,
) -> (Vec<Vec<u64>>, Vec<Vec<u64>>) {
    let inputs: Vec<Vec<f64>> = (entry.inputs.iter())
        .map(|(name, _)| (0..batch).flat_map(|s| library.input(name, s).to_vec()).collect())
        .collect();
    let mut aligned: Vec<Vec<f64>> = (entry.outputs.iter())
        .map(|len| vec![f64::NAN; batch * len])
        .collect();
    let mut shifted_in: Vec<Shifted> = inputs.iter().map(|v| Shifted::new(v)).collect();
    let mut shifted_out: Vec<Shifted> = (aligned.iter()).map(|v| Shifted::new(v)).collect();
    let call = |inputs: Vec<*const f64>, outputs: Vec<*mut f64>| {
        // SAFETY: one pointer per input and output of the entry, each to `batch` states of
        // its array (the table's lengths).
        let status = unsafe { evaluate(f, frame, batch, inputs.as_ptr(), outputs.as_ptr()) };
        assert_eq!(status, 0, "{}: {} on {batch} states", library.prefix, entry.name);
    };
    call(
        inputs.iter().map(|v| v.as_ptr()).collect(),
        aligned.iter_mut().map(|v| v.as_mut_ptr()).collect(),
    );
    call(
        shifted_in.iter_mut().map(|s| s.pointer().cast_const()).collect(),
        shifted_out.iter_mut().map(Shifted::pointer).collect(),
    );
    let bits = |v: &Vec<f64>| v.iter().map(|x| x.to_bits()).collect();
    (
        aligned.iter().map(bits).collect(),
        shifted_out.iter_mut().map(Shifted::bits).collect(),
    )
}

#[test]
fn arrays_at_any_address_give_the_same_bits() {
    let run = run();
    for library in &run.libraries {
        let path = run
            .work
            .join("cargo/debug")
            .join(libloading::library_filename(format!(
                "{}_dynamics",
                library.prefix
            )));
        // SAFETY: a dyngen library runs no code when loaded.
        let shared =
            unsafe { libloading::Library::new(&path) }.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // SAFETY: `P_evaluate` has this type in dyngen.h.
        let evaluate = unsafe {
            *shared
                .get::<Evaluate>(format!("{}_evaluate", library.prefix).as_bytes())
                .expect("P_evaluate")
        };
        let frames = library.model.frames().len();
        let entries = table(&shared, library.prefix);
        assert!(!entries.is_empty());
        for (f, entry) in entries.iter().enumerate() {
            let frame = if entry.takes_frame { frames - 1 } else { 0 };
            // One state, and four: the lanes where the entry has them.
            for batch in [1, 4] {
                let (aligned, shifted) = both_ways(evaluate, library, (f, entry), frame, batch);
                assert!(
                    aligned == shifted,
                    "{}: {} on {batch} states: shifted arrays give other bits",
                    library.prefix,
                    entry.name
                );
                assert!(aligned.iter().flatten().all(|b| !f64::from_bits(*b).is_nan()));
            }
        }
    }
}
