//! Angles and axes that are almost, but not exactly, quarter turns and coordinate axes.
//!
//! Vendor URDFs write π/2 as `1.5708` or `1.57`. The generator folds the zeros and ones of an
//! exact quarter turn (or of an axis along a coordinate axis) away; 3.7e-6 rad off, every
//! rotation stays dense and the generated code does several times the work. Such values are
//! reported with the size of the change that would make them exact, and changed only when the
//! description opts in (`snap_angles: TOLERANCE`), each change a note: never silently, however
//! small (`1.57079632679`, 4.9e-12 off, is reported like `1.5708`). Only a quarter turn to the
//! last bit of `f64` (`1.5707963267948966`) is exact as written (`model::quarter_turns`).

use crate::model::quarter_turns;
use std::f64::consts::FRAC_PI_2;

/// How far from a quarter turn (rad), or from 0 for an axis component, a value is reported.
pub(crate) const REPORTED: f64 = 1e-3;

/// What to do about a near-exact value: keep it, or snap it within a tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Snap(pub Option<f64>);

/// A value that is near an exact one, and what was done.
pub(crate) struct Finding {
    pub message: String,
    /// Snapped (a note), or left as written (a warning).
    pub snapped: bool,
}

impl Snap {
    fn applies(self, distance: f64) -> bool {
        self.0.is_some_and(|tol| distance <= tol)
    }

    fn finding(self, what: String, distance: f64, exact: String) -> Finding {
        let snapped = self.applies(distance);
        let message = if snapped {
            format!("{what} snapped to {exact} (a change of {distance:.1e})")
        } else {
            format!(
                "{what} is {distance:.1e} from {exact}: the generated code keeps it dense; \
                 `snap_angles: {}` makes it exact",
                snap_hint(distance)
            )
        };
        Finding { message, snapped }
    }

    /// Roll, pitch and yaw with the near quarter turns snapped as asked, and what was found.
    pub(crate) fn rpy(self, what: &str, rpy: [f64; 3]) -> ([f64; 3], Vec<Finding>) {
        let mut out = rpy;
        let mut findings = Vec::new();
        for (k, angle) in rpy.iter().enumerate() {
            let turns = (angle / FRAC_PI_2).round();
            let exact = turns * FRAC_PI_2;
            let distance = (angle - exact).abs();
            if quarter_turns(*angle).is_none() && distance <= REPORTED {
                let name = ["roll", "pitch", "yaw"][k];
                let shown = format!("{what} {name} {angle}");
                let f = self.finding(shown, distance, format!("{turns}·π/2"));
                if f.snapped {
                    out[k] = exact;
                }
                findings.push(f);
            }
        }
        (out, findings)
    }

    /// A unit axis with near-zero components snapped as asked (then normalised again).
    pub(crate) fn axis(self, axis: [f64; 3]) -> ([f64; 3], Vec<Finding>) {
        let mut out = axis;
        let mut findings = Vec::new();
        for (k, c) in axis.iter().enumerate() {
            let distance = c.abs();
            if distance > 0.0 && distance <= REPORTED {
                let shown = format!("axis component {} = {c}", ["x", "y", "z"][k]);
                let f = self.finding(shown, distance, "0".into());
                if f.snapped {
                    out[k] = 0.0;
                }
                findings.push(f);
            }
        }
        if out != axis {
            let norm = out.iter().map(|c| c * c).sum::<f64>().sqrt();
            out = out.map(|c| c / norm);
        }
        (out, findings)
    }
}

/// A tolerance that would cover `distance`: the next power of ten.
fn snap_hint(distance: f64) -> String {
    format!("1e{}", distance.log10().ceil() as i32)
}

#[cfg(test)]
// Rounded quarter turns are the point of these tests.
#[allow(clippy::approx_constant)]
mod tests {
    use super::*;

    #[test]
    fn vendor_quarter_turns_are_reported_and_snapped_only_when_asked() {
        let (rpy, f) = Snap(None).rpy("origin", [1.5708, 0.0, -3.1416]);
        assert_eq!(rpy, [1.5708, 0.0, -3.1416]);
        assert_eq!(f.len(), 2);
        assert!(!f[0].snapped);
        assert!(
            f[0].message.contains("origin roll 1.5708 is 3.7e-6 from 1·π/2"),
            "{}",
            f[0].message
        );
        assert!(f[0].message.contains("`snap_angles: 1e-5`"), "{}", f[0].message);
        let (rpy, f) = Snap(Some(1e-4)).rpy("origin", [1.5708, 0.0, -3.1416]);
        assert_eq!(rpy, [FRAC_PI_2, 0.0, -2.0 * FRAC_PI_2]);
        assert!(f.iter().all(|f| f.snapped));
        assert!(
            f[1].message.contains("snapped to -2·π/2 (a change of 7.3e-6)"),
            "{}",
            f[1].message
        );
    }

    #[test]
    fn exact_and_far_values_say_nothing() {
        let (_, f) = Snap(None).rpy("origin", [FRAC_PI_2, 0.3, -std::f64::consts::PI]);
        assert!(f.is_empty());
        let (a, f) = Snap(Some(1e-3)).axis([0.0, 0.6, 0.8]);
        assert!(f.is_empty());
        assert_eq!(a, [0.0, 0.6, 0.8]);
    }

    #[test]
    fn values_a_hair_from_exact_are_kept_and_reported_unless_snapped() {
        let (rpy, f) = Snap(None).rpy("origin", [1.57079632679, 0.0, 1e-12]);
        assert_eq!(rpy, [1.57079632679, 0.0, 1e-12]);
        assert_eq!(f.len(), 2);
        assert!(f.iter().all(|f| !f.snapped));
        assert!(
            f[0].message
                .contains("origin roll 1.57079632679 is 4.9e-12 from 1·π/2")
                && f[0].message.contains("`snap_angles: 1e-11`"),
            "{}",
            f[0].message
        );
        let (rpy, f) = Snap(Some(1e-9)).rpy("origin", [1.57079632679, 0.0, 1e-12]);
        assert_eq!(rpy, [FRAC_PI_2, 0.0, 0.0]);
        assert!(f.iter().all(|f| f.snapped && f.message.contains("snapped to")));
    }

    #[test]
    fn near_axes_snap_and_stay_unit() {
        let (a, f) = Snap(Some(1e-3)).axis([2e-4, 0.0, 1.0]);
        assert_eq!(a, [0.0, 0.0, 1.0]);
        assert_eq!(f.len(), 1);
        let (a, f) = Snap(None).axis([2e-4, 0.0, 1.0]);
        assert_eq!(a, [2e-4, 0.0, 1.0]);
        assert!(
            f[0].message
                .contains("axis component x = 0.0002 is 2.0e-4 from 0"),
            "{}",
            f[0].message
        );
    }
}
