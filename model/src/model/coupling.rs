//! Mimic joints: tree joints that move with another joint instead of having a coordinate.
//!
//! A mimic joint `j` of master `k` sits at `q_j = multiplier·q_k + offset` (URDF `<mimic>`,
//! Pinocchio 4's `JointModelMimic`). The tree still has one body per moving joint, mimic joints
//! included, so θ keeps ten parameters per body; the robot's coordinates `q` are the joints
//! that mimic nothing, in tree order. With `G` the constant (tree joints × coordinates) matrix
//! of multipliers, `q_tree = G q + o`, `q̇_tree = G q̇` and `q̈_tree = G q̈` (see
//! `docs/dynamics.md`, "Mimic joints").

/// Joint `j` follows `master`: `q_j = multiplier·q_master + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mimic {
    /// Index (in [`Model::joints`](super::Model::joints)) of the joint followed; never itself
    /// a mimic joint (the loaders resolve chains).
    pub master: usize,
    /// Finite and non-zero.
    pub multiplier: f64,
    /// Finite (rad or m).
    pub offset: f64,
}

/// Where a tree joint's position comes from: coordinate `coordinate` of `q`, times `multiplier`,
/// plus `offset` (`1` and `0` for a joint that is its own coordinate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoordinateMap {
    pub coordinate: usize,
    pub multiplier: f64,
    pub offset: f64,
}

/// Checks one model's mimic list against its joints: one entry per joint, masters that exist,
/// are not the joint itself nor mimic joints, finite non-zero multipliers, finite offsets.
pub(super) fn check_mimics(mimics: &[Option<Mimic>], names: &[&str]) -> Result<(), String> {
    if mimics.len() != names.len() {
        return Err(format!(
            "{} mimic entries for {} joints",
            mimics.len(),
            names.len()
        ));
    }
    for (j, m) in mimics.iter().enumerate() {
        let Some(m) = m else { continue };
        let name = names[j];
        if m.master >= names.len() || m.master == j {
            return Err(format!(
                "joint '{name}': mimic master index {} is invalid",
                m.master
            ));
        }
        if mimics[m.master].is_some() {
            return Err(format!(
                "joint '{name}': its master '{}' is itself a mimic joint",
                names[m.master]
            ));
        }
        if !(m.multiplier.is_finite() && m.multiplier != 0.0 && m.offset.is_finite()) {
            return Err(format!(
                "joint '{name}': mimic multiplier {} or offset {} is invalid",
                m.multiplier, m.offset
            ));
        }
    }
    Ok(())
}

/// Per tree joint, where its position comes from (coordinates numbered in tree order).
pub(super) fn coordinate_maps(mimics: &[Option<Mimic>], joints: usize) -> Vec<CoordinateMap> {
    let mimic = |j: usize| mimics.get(j).copied().flatten();
    let mut coordinate_of = vec![0; joints];
    let mut next = 0;
    for (j, c) in coordinate_of.iter_mut().enumerate() {
        if mimic(j).is_none() {
            *c = next;
            next += 1;
        }
    }
    (0..joints)
        .map(|j| match mimic(j) {
            None => CoordinateMap {
                coordinate: coordinate_of[j],
                multiplier: 1.0,
                offset: 0.0,
            },
            Some(m) => CoordinateMap {
                coordinate: coordinate_of[m.master],
                multiplier: m.multiplier,
                offset: m.offset,
            },
        })
        .collect()
}
