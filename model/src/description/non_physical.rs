//! Links whose inertia no real body can have, and what the description's `inertia:` choice
//! does with each: a warning (`as_written`, the default), the nearest physical inertia with a
//! note (`repair`), or an error (`strict`); each said once per link, with its place and how far
//! from physical the inertia is ([`InertiaDefect`]).
//!
//! Judged in two steps. Each link's tensor is examined where it is read ([`examine`]): strict
//! refuses at once, repair replaces the tensor before the link is welded into its body. Whether
//! a gross defect (wrong numbers, not rounded ones) is refused needs the tree: a link welded
//! to the fixed base never enters the dynamics, so it is only warned about; that is decided
//! when the links' carriers are known ([`report`]).

use super::choices::NonPhysicalInertia;
use super::error::{item, DescriptionError, Diagnostics};
use super::source_map::{link_path, SourceMap};
use crate::model::physical_inertia::{moments_text, nearest_physical, percent, short, GROSS_DEFECT};
use crate::model::{inertia_defect, InertiaDefect, InertiaDefectKind};
use nalgebra::Matrix3;

/// A link whose inertia is not physical, found while its inertial was read.
pub(crate) struct NonPhysicalLink {
    /// The link's index in the description.
    pub link: usize,
    pub name: String,
    pub defect: InertiaDefect,
    /// The tensor as written and as repaired (inertial frame), when repaired.
    pub repair: Option<(Matrix3<f64>, Matrix3<f64>)>,
}

/// The tensor to use for a link (as written, or repaired when asked), and its defect if any;
/// an error message when the choice is `strict` and the inertia is not physical.
pub(crate) fn examine(
    link: usize,
    name: &str,
    mass: f64,
    tensor: &Matrix3<f64>,
    choice: NonPhysicalInertia,
) -> Result<(Matrix3<f64>, Option<NonPhysicalLink>), String> {
    let Some(defect) = inertia_defect(mass, tensor) else {
        return Ok((*tensor, None));
    };
    let (used, repair) = match choice {
        NonPhysicalInertia::Strict => return Err(format!("{defect}; `inertia: strict` refuses it")),
        NonPhysicalInertia::AsWritten => (*tensor, None),
        NonPhysicalInertia::Repair => {
            let repaired = nearest_physical(mass, tensor);
            (repaired, Some((*tensor, repaired)))
        }
    };
    let found = NonPhysicalLink {
        link,
        name: name.to_owned(),
        defect,
        repair,
    };
    Ok((used, Some(found)))
}

/// One warning or note per link of `found`, or the error for a gross defect kept as written
/// on a link that moves (`welded_to_base(link)` false).
pub(crate) fn report(
    found: &[NonPhysicalLink],
    welded_to_base: impl Fn(usize) -> bool,
    map: &SourceMap,
    diags: &mut Diagnostics,
) -> Result<(), DescriptionError> {
    for f in found {
        let path = format!("{}.inertial.inertia", link_path(f.link));
        let label = item("link", &f.name);
        let defect = &f.defect;
        match &f.repair {
            Some((before, after)) => {
                let msg = format!(
                    "{defect}; repaired to the nearest physical inertia: principal moments {} → {} \
                     kg·m², ({}) → ({})",
                    moments(before),
                    moments(after),
                    entries(before),
                    entries(after)
                );
                diags.notes.push(map.diagnostic(&path, Some(&label), &msg));
            }
            None if welded_to_base(f.link) => {
                let msg = format!(
                    "{defect}; loaded as written: the link is welded to the fixed base and never enters \
                     the dynamics"
                );
                diags.warnings.push(map.diagnostic(&path, Some(&label), &msg));
            }
            None if f.defect.is_gross() => {
                let msg = format!(
                    "{defect}{}: check the values (kg·m², about the centre of mass), or give \
                     `inertia: repair` for the nearest physical inertia",
                    beyond(defect)
                );
                return Err(map.error(&path, msg).about(label));
            }
            None => {
                let msg = format!(
                    "{defect}; loaded as written (`inertia: repair` gives the nearest physical inertia)"
                );
                diags.warnings.push(map.diagnostic(&path, Some(&label), &msg));
            }
        }
    }
    Ok(())
}

/// Why a gross defect is refused: how far beyond the bound it is.
fn beyond(defect: &InertiaDefect) -> String {
    let bound = percent(GROSS_DEFECT);
    match defect.kind {
        InertiaDefectKind::TriangleInequality => {
            format!(", more than the {bound} loaded as written")
        }
        _ => format!(
            ", which breaks the triangle inequality by {} (I3 − I1 − I2 = {} kg·m²), more than the \
             {bound} loaded as written",
            percent(defect.relative_excess()),
            short(defect.excess())
        ),
    }
}

fn moments(tensor: &Matrix3<f64>) -> String {
    moments_text(&crate::model::principal_moments(tensor))
}

/// The six entries as a description writes them.
fn entries(t: &Matrix3<f64>) -> String {
    format!(
        "ixx {}, ixy {}, ixz {}, iyy {}, iyz {}, izz {}",
        short(t[(0, 0)]),
        short(t[(0, 1)]),
        short(t[(0, 2)]),
        short(t[(1, 1)]),
        short(t[(1, 2)]),
        short(t[(2, 2)])
    )
}
