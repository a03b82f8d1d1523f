//! How a result written in place starts: small ones from a constant zero (a few inline
//! stores), mid-sized ones from `fill_zero()` (a run of vector stores inside the kernel, no
//! library call), large ones from a constant zero again (one `memset` into the result, where the
//! compiler would otherwise fill a temporary and copy it).

use crate::emitted_code::emitted;

/// The initialisers of every result of type `ty` written in place (`let mut out: ty = …;`),
/// without whitespace.
fn starts(code: &str, ty: &str) -> Vec<String> {
    let head = format!("let mut out: {ty} = ");
    code.match_indices(&head)
        .map(|(at, _)| {
            let rest = &code[at + head.len()..];
            let text: String = rest[..rest.find(';').expect("a complete statement")]
                .split_whitespace()
                .collect();
            // The formatter may break a call over lines, leaving a trailing comma.
            text.replace(",)", ")")
        })
        .collect()
}

#[test]
fn results_start_from_the_zero_their_size_calls_for() {
    let arm7 = emitted("robots/arm7.yaml");
    // `D`: 392 bytes.
    let small = starts(&arm7, "SMatrix<f64, 7, 7>");
    assert!(
        !small.is_empty() && small.iter().all(|s| s == "SMatrix::zeros()"),
        "{small:?}"
    );
    // The regressors: 3,920 bytes.
    let mid = starts(&arm7, "SMatrix<f64, 7, 70>");
    assert!(
        !mid.is_empty()
            && mid
                .iter()
                .all(|s| s == "SMatrix::from_element(dyngen_runtime::__private::fill_zero())"),
        "{mid:?}"
    );
    // With joint friction and armature the regressors have 98 columns: 5,488 bytes.
    let friction = emitted("robots/arm7_friction.yaml");
    let large = starts(&friction, "SMatrix<f64, 7, 98>");
    assert!(
        !large.is_empty() && large.iter().all(|s| s == "SMatrix::zeros()"),
        "{large:?}"
    );
}
