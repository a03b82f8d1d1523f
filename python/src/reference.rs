//! Reference frames as Python spells them: Pinocchio's names in lower case.

use dyngen_runtime::ReferenceFrame;
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

/// The reference frames by name, in `ReferenceFrame`'s order.
pub const REFERENCE_FRAMES: [(&str, ReferenceFrame); 3] = [
    ("local", ReferenceFrame::Local),
    ("world", ReferenceFrame::World),
    ("local_world_aligned", ReferenceFrame::LocalWorldAligned),
];

/// `"local"`, `"world"` or `"local_world_aligned"` (any case).
pub fn reference_frame(name: &str) -> PyResult<ReferenceFrame> {
    let lower = name.to_ascii_lowercase();
    REFERENCE_FRAMES
        .iter()
        .find(|(n, _)| *n == lower)
        .map(|&(_, r)| r)
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown reference frame '{name}': expected \"local\", \"world\" or \"local_world_aligned\""
            ))
        })
}
