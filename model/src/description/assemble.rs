//! The checked tree → [`Model`]: fixed and locked joints welded away, inertias merged into the
//! moving body that carries them, placements composed, the end-effector frame chosen.
//!
//! Every link ends up on a *carrier*: the moving joint whose body it is part of (or the base),
//! at a fixed placement in that joint's frame. A moving joint's origin is then its parent
//! link's placement composed with its own URDF origin, which is what [`crate::model::Joint`]
//! wants: the frame relative to the parent *moving* joint, not to the parent link.

use super::choices::{Choices, FrameSelection, FrameSpec};
use super::contacts;
use super::error::{item, num, render, vec3, DescriptionError, Diagnostics};
use super::items::{too_large, JointShape, Motion};
use super::joint_parameters;
use super::near_exact::{Snap, REPORTED};
use super::non_physical::{self, NonPhysicalLink};
use super::raw::RawRobot;
use super::source_map::{joint_path, link_path, SourceMap};
use super::tree::Topology;
use crate::frame_names::frame_identifiers;
use crate::model::{exact_sin_cos, from_xyz_rpy, Body, Frame, Inertia, Joint, JointKind, Mimic, Model, Pose};
use nalgebra::{Matrix3, Vector3};

/// Gravity when the description gives none (z up).
pub(crate) const DEFAULT_GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// The user's choices as the loader uses them: with the description's `name:` and the file
/// they are written in (a YAML description, or the URDF itself when the caller made them).
pub(crate) struct Settings<'a> {
    /// A YAML description's `name:`, over the robot's own.
    pub name: Option<&'a str>,
    pub choices: &'a Choices,
    /// Places of `end_effector`, `frames[k]`, `gravity`, `locked_joints.<joint>`,
    /// `snap_angles`, `inertia`, `joint_parameters…`.
    pub map: &'a SourceMap,
}

impl Settings<'_> {
    /// The snapping asked for, checked: a tolerance in (0, 1e-3] rad.
    pub fn snap(&self) -> Result<Snap, DescriptionError> {
        match self.choices.snap_angles {
            Some(t) if !(t > 0.0 && t <= REPORTED) => Err(self.map.error(
                "snap_angles",
                format!("snap_angles {t} must be a tolerance in radians, above 0 and at most {REPORTED}"),
            )),
            t => Ok(Snap(t)),
        }
    }
}

/// Everything the assembly needs, checked.
pub(crate) struct Checked<'a> {
    pub raw: &'a RawRobot,
    /// Where the robot's links and joints are written.
    pub robot_map: &'a SourceMap,
    pub links: &'a [Inertia],
    /// Links whose inertia is not physical, to report once their carriers are known.
    pub non_physical: &'a [NonPhysicalLink],
    pub joints: &'a [JointShape],
    pub topo: &'a Topology,
}

/// Builds the model; see the module docs.
pub(crate) fn assemble(
    c: &Checked<'_>,
    settings: &Settings<'_>,
    diags: &mut Diagnostics,
) -> Result<Model, DescriptionError> {
    let name = match settings.name.map(str::to_owned).or_else(|| c.raw.name.clone()) {
        Some(n) => n,
        None => return Err(DescriptionError::new(&c.robot_map.file, "the robot has no name")),
    };
    let gravity = settings.choices.gravity.unwrap_or(DEFAULT_GRAVITY);
    if !gravity.iter().all(|g| g.is_finite()) {
        return Err(settings
            .map
            .error("gravity", format!("gravity {} is not finite", vec3(&gravity))));
    }
    if let Some(msg) = too_large(&gravity, "gravity") {
        return Err(settings.map.error("gravity", msg));
    }
    let locked = locked_values(c, settings)?;
    let follows = check_mimics(c, &locked, settings, diags)?;

    // Carrier and placement of every link, moving joints in depth-first order.
    let n_links = c.raw.links.len();
    let mut carrier: Vec<Option<usize>> = vec![None; n_links];
    let mut placement: Vec<Pose> = vec![Pose::identity(); n_links];
    let mut joints = Vec::new();
    let mut bodies: Vec<Option<Inertia>> = Vec::new();
    let mut body_names = Vec::new();
    let mut raw_index = Vec::new();
    for &j in &c.topo.joint_order {
        let (p, ch) = (c.topo.parent_link[j], c.topo.child_link[j]);
        let shape = &c.joints[j];
        let at_joint = placement[p].compose(&shape.origin);
        match (shape.motion, locked[j]) {
            (Motion::Moving(kind), None) => {
                carrier[ch] = Some(joints.len());
                placement[ch] = Pose::identity();
                joints.push(Joint {
                    name: c.raw.joints[j].name.clone(),
                    parent: carrier[p],
                    kind,
                    origin: at_joint,
                    axis: shape.axis,
                    limits: shape.limits,
                });
                bodies.push(None);
                body_names.push(c.raw.links[ch].name.clone());
                raw_index.push(j);
            }
            (Motion::Moving(kind), Some(q)) => {
                carrier[ch] = carrier[p];
                placement[ch] = at_joint.compose(&joint_motion(kind, &shape.axis, q));
            }
            (Motion::Fixed, _) => {
                carrier[ch] = carrier[p];
                placement[ch] = at_joint;
            }
        }
    }
    if joints.is_empty() {
        return Err(DescriptionError::new(
            &c.robot_map.file,
            "the robot has no moving joints (all are fixed or locked)",
        ));
    }

    // A link on a fixed base never enters the dynamics, so its inertia's defects are only said.
    let floating = settings.choices.floating_base;
    non_physical::report(
        c.non_physical,
        |l| !floating && carrier[l].is_none(),
        c.robot_map,
        diags,
    )?;

    // Weld every link into its carrier's body; links on a fixed base do not move and drop
    // out, links on a floating one make up the base body.
    let zero = Inertia {
        mass: 0.0,
        com: Vector3::zeros(),
        inertia_com: Matrix3::zeros(),
    };
    let mut base_body = zero;
    for &l in &c.topo.link_order {
        let part = c.links[l].transformed(&placement[l]);
        match carrier[l] {
            Some(k) => {
                bodies[k] = Some(match bodies[k] {
                    None => part,
                    Some(body) => body.merged(&part),
                })
            }
            None => base_body = base_body.merged(&part),
        }
    }
    let bodies = bodies
        .into_iter()
        .zip(body_names)
        .map(|(inertia, name)| Body {
            name,
            inertia: inertia.unwrap_or(zero),
        })
        .collect();

    let end_effector = end_effector(c, settings, &carrier, &placement, &joints, diags)?;
    let frames = named_frames(c, settings, &end_effector, &carrier, &placement, diags)?;
    let raw_dynamics: Vec<_> = c.raw.joints.iter().map(|j| j.dynamics).collect();
    // Only moving joints that are not locked carry joint-level parameters.
    let moving = |r: usize| matches!(c.joints[r].motion, Motion::Moving(_)) && locked[r].is_none();
    let sources = joint_parameters::JointSources {
        raw_index: &raw_index,
        raw: &raw_dynamics,
        moving: &moving,
        joint_by_name: &c.topo.joint_by_name,
        robot_map: c.robot_map,
    };
    let joint_terms = joint_parameters::joint_terms(
        settings.choices.joint_parameters.as_ref(),
        settings.map,
        &joints,
        &sources,
    )?;
    let mimics = model_mimics(&follows, &raw_index);
    if !joint_terms.kinds.is_empty() && mimics.iter().any(Option::is_some) {
        let msg = "joint-level parameters (armature, friction, offset) are not supported on a \
                   robot with mimic joints; lock the mimic joints or leave out \
                   `joint_parameters.columns`";
        return Err(settings.map.error("joint_parameters.columns", msg));
    }
    let base = floating.then(|| Body {
        name: c.raw.links[c.topo.root].name.clone(),
        inertia: base_body,
    });
    Model::new(name, joints, bodies, Vector3::from(gravity), end_effector)
        .and_then(|m| match base {
            Some(body) => m.with_floating_base(body),
            None => Ok(m),
        })
        .and_then(|m| m.with_frames(frames))
        .and_then(|m| m.with_joint_terms(joint_terms))
        .and_then(|m| m.with_mimics(mimics))
        .map_err(|e| internal_error(c, e))
        .and_then(|m| {
            let contacts = contacts::resolve(&settings.choices.contacts, m.frames(), settings.map)?;
            // Each contact passed `resolve`: what is left is the set's, held at its key.
            m.with_contacts(contacts)
                .map_err(|e| settings.map.error("contacts", e.0))
        })
}

/// A model the checks above let through but `Model` refuses: a bug of the loader's.
fn internal_error(c: &Checked<'_>, e: crate::model::ModelError) -> DescriptionError {
    DescriptionError::new(
        &c.robot_map.file,
        format!("internal error: the model breaks an invariant: {e}"),
    )
}

/// Per model joint (`raw_index[i]` is its raw joint), the model joint it follows.
fn model_mimics(follows: &[Option<Follows>], raw_index: &[usize]) -> Vec<Option<Mimic>> {
    raw_index
        .iter()
        .map(|&r| {
            follows[r].map(|f| Mimic {
                // The master moves and is not locked (`resolve`), so it is a model joint.
                master: raw_index
                    .iter()
                    .position(|&k| k == f.master)
                    .unwrap_or(usize::MAX),
                multiplier: f.multiplier,
                offset: f.offset,
            })
        })
        .collect()
}

/// The pose a joint adds at position `q`: rotation about, or translation along, its axis.
fn joint_motion(kind: JointKind, axis: &Vector3<f64>, q: f64) -> Pose {
    match kind {
        JointKind::Revolute => {
            let (s, c) = exact_sin_cos(q);
            let k = axis.cross_matrix();
            Pose {
                rotation: Matrix3::identity() + k * s + k * k * (1.0 - c),
                translation: Vector3::zeros(),
            }
        }
        JointKind::Prismatic => Pose {
            rotation: Matrix3::identity(),
            translation: axis * q,
        },
    }
}

/// Locked position per joint (`None`: not locked), with every entry checked.
fn locked_values(c: &Checked<'_>, settings: &Settings<'_>) -> Result<Vec<Option<f64>>, DescriptionError> {
    let mut locked = vec![None; c.raw.joints.len()];
    for (name, q) in &settings.choices.locked_joints {
        let path = format!("locked_joints.{name}");
        let err = |msg: String| {
            settings
                .map
                .error(&path, msg)
                .about(format!("locked joint '{name}'"))
        };
        let Some(&j) = c.topo.joint_by_name.get(name) else {
            return Err(err(
                "unknown locked joint: the robot has no joint of that name".into()
            ));
        };
        if locked[j].is_some() {
            return Err(err("the joint is locked twice".into()));
        }
        if !q.is_finite() {
            return Err(err(format!("position {} is not finite", num(*q))));
        }
        if c.joints[j].motion == Motion::Fixed {
            return Err(err("the joint is fixed; only moving joints can be locked".into()));
        }
        if let Some(l) = &c.joints[j].limits {
            if *q < l.lower || *q > l.upper {
                let msg = format!(
                    "position {} is outside the joint limits [{}, {}]",
                    num(*q),
                    num(l.lower),
                    num(l.upper)
                );
                return Err(err(msg));
            }
        }
        locked[j] = Some(*q);
    }
    Ok(locked)
}

/// A moving mimic joint resolved to the joint that is its coordinate: `q = multiplier·q_master
/// + offset`, `master` a raw joint index.
#[derive(Clone, Copy)]
struct Follows {
    master: usize,
    multiplier: f64,
    offset: f64,
}

/// Mimic joints: a moving, unlocked mimic joint follows its master (chains of mimic joints are
/// resolved to the first joint that mimics nothing, as Pinocchio does); a locked one stays
/// locked, with a warning when it then does not follow its master. Per raw joint, whom it
/// follows.
fn check_mimics(
    c: &Checked<'_>,
    locked: &[Option<f64>],
    settings: &Settings<'_>,
    diags: &mut Diagnostics,
) -> Result<Vec<Option<Follows>>, DescriptionError> {
    let mut follows = vec![None; c.raw.joints.len()];
    for (j, joint) in c.raw.joints.iter().enumerate() {
        let Some(m) = &joint.mimic else { continue };
        let path = format!("{}.mimic", joint_path(j));
        let label = item("joint", &joint.name);
        if c.joints[j].motion == Motion::Fixed {
            // Common in URDFs expanded from xacro macros; a fixed joint has nothing to follow.
            let msg = format!("<mimic> of '{}' on a fixed joint is ignored", m.joint);
            diags
                .warnings
                .push(c.robot_map.diagnostic(&path, Some(&label), &msg));
            continue;
        }
        let Some(&target) = c.topo.joint_by_name.get(&m.joint) else {
            let msg = format!("mimics joint '{}', which is not defined", m.joint);
            return Err(c.robot_map.error(&path, msg).about(label));
        };
        let Some(q) = locked[j] else {
            let err = |msg: String| c.robot_map.error(&path, msg).about(label.clone());
            follows[j] = Some(resolve(c, locked, j, target, m.multiplier, m.offset).map_err(err)?);
            continue;
        };
        let msg = match locked[target] {
            Some(qt) if (q - (m.multiplier * qt + m.offset)).abs() > 1e-12 => format!(
                "locked at {} but it mimics '{}' locked at {} (multiplier {}, offset {})",
                num(q),
                m.joint,
                num(qt),
                num(m.multiplier),
                num(m.offset)
            ),
            Some(_) => continue,
            None => format!(
                "mimics '{}' but is locked on its own: it will not follow '{}'",
                m.joint, m.joint
            ),
        };
        let at = format!("locked_joints.{}", joint.name);
        diags
            .warnings
            .push(settings.map.diagnostic(&at, Some(&label), &msg));
    }
    Ok(follows)
}

/// The joint that unlocked mimic joint `j` finally follows, from its `<mimic>` of `target`
/// with `multiplier` and `offset`: through mimic joints that mimic further, composing
/// `q = m₁ (m₂ q_k + o₂) + o₁`. An error message when it cannot be followed.
fn resolve(
    c: &Checked<'_>,
    locked: &[Option<f64>],
    j: usize,
    target: usize,
    multiplier: f64,
    offset: f64,
) -> Result<Follows, String> {
    let name = |k: usize| c.raw.joints[k].name.as_str();
    if multiplier == 0.0 {
        return Err(format!(
            "mimics joint '{}' with multiplier 0: the joint would never move; lock it \
             (locked_joints) instead",
            name(target)
        ));
    }
    let mut chain = vec![j];
    let (mut k, mut m, mut o) = (target, multiplier, offset);
    loop {
        if chain.contains(&k) {
            chain.push(k);
            let names: Vec<String> = chain.iter().map(|&i| format!("'{}'", name(i))).collect();
            return Err(match chain.len() {
                2 => "mimics itself".to_owned(),
                _ => format!("mimic joints {} form a cycle", names.join(" → ")),
            });
        }
        if c.joints[k].motion == Motion::Fixed {
            return Err(format!("mimics joint '{}', which is fixed", name(k)));
        }
        if let Some(qk) = locked[k] {
            return Err(format!(
                "mimics joint '{}', which is locked at {}: lock '{}' too, at {} (multiplier·{} + \
                 offset)",
                name(k),
                num(qk),
                name(j),
                num(m * qk + o),
                num(qk)
            ));
        }
        let Some(next) = &c.raw.joints[k].mimic else {
            return Ok(Follows {
                master: k,
                multiplier: m,
                offset: o,
            });
        };
        let Some(&after) = c.topo.joint_by_name.get(&next.joint) else {
            return Err(format!(
                "mimics joint '{}', which mimics '{}', which is not defined",
                name(k),
                next.joint
            ));
        };
        if next.multiplier == 0.0 {
            return Err(format!(
                "mimics joint '{}', which mimics '{}' with multiplier 0",
                name(k),
                next.joint
            ));
        }
        chain.push(k);
        (k, m, o) = (after, m * next.multiplier, m * next.offset + o);
    }
}

/// The end-effector frame: the one asked for, or the leaf link at the end of the longest chain.
fn end_effector(
    c: &Checked<'_>,
    settings: &Settings<'_>,
    carrier: &[Option<usize>],
    placement: &[Pose],
    joints: &[Joint],
    diags: &mut Diagnostics,
) -> Result<Frame, DescriptionError> {
    let spec = match &settings.choices.end_effector {
        Some(spec) => spec.clone(),
        None => {
            let leaf = default_leaf(c, carrier, joints)?;
            let leaves = c
                .topo
                .link_order
                .iter()
                .filter(|&&l| c.topo.children[l].is_empty())
                .count();
            let name = &c.raw.links[leaf].name;
            let why = if leaves == 1 {
                "the only leaf link".to_owned()
            } else {
                let depth = carrier[leaf].map_or(0, |k| chain_len(joints, k));
                format!("the end of the longest chain, {depth} moving joints")
            };
            let msg = format!("no end-effector given: using leaf link '{name}' ({why})");
            diags.notes.push(render(&settings.map.file, None, None, &msg));
            FrameSpec::link(name.clone())
        }
    };
    let frame = frame_from_spec(
        c,
        settings,
        &spec,
        "end_effector",
        "end-effector",
        carrier,
        placement,
    )?;
    if frame.parent.is_none() {
        let msg = format!(
            "link '{}' is part of the floating base body: the end-effector must ride on a moving \
             joint's body (name a frame on the base under `frames`)",
            spec.link
        );
        return Err(settings
            .map
            .error("end_effector", msg)
            .about(format!("end-effector '{}'", spec.frame_name())));
    }
    Ok(frame)
}

/// A frame the description names: a link's frame moved by the spec's offset. `path` is where
/// the spec is written (`end_effector`, `frames[2]`), `what` how messages call it.
fn frame_from_spec(
    c: &Checked<'_>,
    settings: &Settings<'_>,
    spec: &FrameSpec,
    path: &str,
    what: &str,
    carrier: &[Option<usize>],
    placement: &[Pose],
) -> Result<Frame, DescriptionError> {
    let err = |msg: String| {
        settings
            .map
            .error(path, msg)
            .about(format!("{what} '{}'", spec.frame_name()))
    };
    let Some(&link) = c.topo.link_by_name.get(&spec.link) else {
        return Err(err(format!("link '{}' is not defined", spec.link)));
    };
    if !(spec.xyz.iter().chain(&spec.rpy).all(|v| v.is_finite())) {
        return Err(err("offset xyz/rpy is not finite".into()));
    }
    let parent = carrier[link];
    if parent.is_none() && !settings.choices.floating_base {
        let msg = format!(
            "link '{}' does not move with any joint (it is fixed to the base)",
            spec.link
        );
        return Err(err(msg));
    }
    let offset = from_xyz_rpy(spec.xyz, spec.rpy);
    Ok(Frame {
        name: spec.frame_name().to_owned(),
        parent,
        placement: placement[link].compose(&offset),
    })
}

/// The frames `frames:` asks for besides the end-effector, in the order written (`all`: every
/// link that moves, in the description's link order). A name used twice is an error at its
/// second use; the end-effector's name may be listed only for the end-effector itself.
fn named_frames(
    c: &Checked<'_>,
    settings: &Settings<'_>,
    end_effector: &Frame,
    carrier: &[Option<usize>],
    placement: &[Pose],
    diags: &mut Diagnostics,
) -> Result<Vec<Frame>, DescriptionError> {
    let specs: Vec<(String, FrameSpec)> = match &settings.choices.frames {
        FrameSelection::EndEffector => Vec::new(),
        FrameSelection::Listed(specs) => specs
            .iter()
            .enumerate()
            .map(|(k, spec)| (format!("frames[{k}]"), spec.clone()))
            .collect(),
        FrameSelection::AllLinks => (0..c.raw.links.len())
            .filter(|&l| carrier[l].is_some() || settings.choices.floating_base)
            .map(|l| ("frames".to_owned(), FrameSpec::link(c.raw.links[l].name.clone())))
            .collect(),
    };
    let mut frames: Vec<Frame> = Vec::new();
    for (path, spec) in &specs {
        let frame = frame_from_spec(c, settings, spec, path, "frame", carrier, placement)?;
        if frame == *end_effector {
            continue;
        }
        let taken = frames.iter().any(|f| f.name == frame.name)
            || (frame.name == end_effector.name && frame != *end_effector);
        if taken {
            let msg = format!(
                "frame name '{}' is already used{}; give this frame another `name`",
                frame.name,
                match frame.name == end_effector.name {
                    true => " by the end-effector, which is a different frame",
                    false => " by an earlier frame",
                }
            );
            return Err(settings.map.error(path, msg));
        }
        frames.push(frame);
    }
    note_suffixed_names(end_effector, &frames, settings.map, diags);
    Ok(frames)
}

/// One note per frame whose name generated code spells like an earlier frame's, with the
/// spellings it gets instead (`crate::frame_names`: the rule, and the one list the generator
/// uses too).
fn note_suffixed_names(end_effector: &Frame, frames: &[Frame], map: &SourceMap, diags: &mut Diagnostics) {
    let all: Vec<&Frame> = std::iter::once(end_effector).chain(frames).collect();
    let ids = frame_identifiers(all.iter().map(|f| f.name.as_str()));
    for (k, id) in ids.iter().enumerate() {
        let Some(earlier) = id.suffixed_after else {
            continue;
        };
        let (first, alike) = (&ids[earlier], &all[k].name);
        let own = &frame_identifiers([alike.as_str()])[0];
        let spelled = match own.variant == first.variant {
            true => format!("`Frame::{}`", first.variant),
            false => format!("`{}` in function names", first.snake),
        };
        let msg = format!(
            "frames '{}' and '{alike}' are both spelled {spelled} in generated code: '{alike}' is \
             `Frame::{}`, `{}` in function names (`frame_pose_{}`)",
            all[earlier].name, id.variant, id.snake, id.snake
        );
        diags.notes.push(map.diagnostic("frames", None, &msg));
    }
}

/// Leaf link whose chain has the most moving joints; ties go to the first in depth-first order.
fn default_leaf(
    c: &Checked<'_>,
    carrier: &[Option<usize>],
    joints: &[Joint],
) -> Result<usize, DescriptionError> {
    let mut best: Option<(usize, usize)> = None;
    for &l in &c.topo.link_order {
        if !c.topo.children[l].is_empty() {
            continue;
        }
        if let Some(k) = carrier[l] {
            let depth = chain_len(joints, k);
            if best.is_none_or(|(_, d)| depth > d) {
                best = Some((l, depth));
            }
        }
    }
    best.map(|(l, _)| l).ok_or_else(|| {
        let root = &c.raw.links[c.topo.root].name;
        c.robot_map
            .error(
                &link_path(c.topo.root),
                "no end-effector given and no leaf link moves with a joint",
            )
            .about(item("link", root))
    })
}

/// Number of moving joints from the base to joint `k` inclusive.
fn chain_len(joints: &[Joint], k: usize) -> usize {
    let mut n = 1;
    let mut j = k;
    while let Some(p) = joints.get(j).and_then(|jt| jt.parent) {
        n += 1;
        j = p;
    }
    n
}
