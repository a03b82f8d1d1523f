//! The shape of the link/joint graph: names resolved, exactly one root, no cycles, every link
//! reachable, and the depth-first order that fixes the order of the joints.
//!
//! Order: depth-first from the root, the child joints of a link in the order they appear in
//! the file. This is what urdfdom (and so Pinocchio, ROS) does, so joint indices agree with
//! the tools users compare against.

use super::error::{item, DescriptionError};
use super::raw::RawRobot;
use super::source_map::{joint_path, link_path, SourceMap};
use std::collections::HashMap;

/// The resolved graph. Links and joints are indices into the raw description.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Topology {
    /// The one link without a parent joint (the fixed base).
    pub root: usize,
    /// Per joint: parent and child link.
    pub parent_link: Vec<usize>,
    pub child_link: Vec<usize>,
    /// Per link: its child joints, in file order.
    pub children: Vec<Vec<usize>>,
    /// All joints, depth-first from the root.
    pub joint_order: Vec<usize>,
    /// All links, depth-first from the root (root first).
    pub link_order: Vec<usize>,
    pub link_by_name: HashMap<String, usize>,
    pub joint_by_name: HashMap<String, usize>,
}

/// Resolves names and checks that the links and joints form one tree.
pub(crate) fn topology(raw: &RawRobot, map: &SourceMap) -> Result<Topology, DescriptionError> {
    if raw.links.is_empty() {
        return Err(DescriptionError::new(&map.file, "the robot has no links"));
    }
    let link_by_name = unique_names(raw.links.iter().map(|l| l.name.as_str()), "link", link_path, map)?;
    let joint_by_name = unique_names(
        raw.joints.iter().map(|j| j.name.as_str()),
        "joint",
        joint_path,
        map,
    )?;

    let n_links = raw.links.len();
    let mut parent_joint: Vec<Option<usize>> = vec![None; n_links];
    let mut parent_link = Vec::with_capacity(raw.joints.len());
    let mut child_link = Vec::with_capacity(raw.joints.len());
    let mut children = vec![Vec::new(); n_links];
    for (j, joint) in raw.joints.iter().enumerate() {
        let label = item("joint", &joint.name);
        let resolve = |name: &str, role: &str| {
            link_by_name.get(name).copied().ok_or_else(|| {
                let msg = format!("{role} link '{name}' is not defined");
                map.error(&format!("{}.{role}", joint_path(j)), msg)
                    .about(label.clone())
            })
        };
        let p = resolve(&joint.parent, "parent")?;
        let c = resolve(&joint.child, "child")?;
        if p == c {
            let msg = format!(
                "parent and child are the same link '{}': a joint cannot close a cycle",
                joint.parent
            );
            return Err(map.error(&joint_path(j), msg).about(label));
        }
        if let Some(other) = parent_joint[c] {
            let msg = format!(
                "link '{}' already hangs from joint '{}'; a link can have only one parent joint",
                joint.child, raw.joints[other].name
            );
            return Err(map.error(&format!("{}.child", joint_path(j)), msg).about(label));
        }
        parent_joint[c] = Some(j);
        parent_link.push(p);
        child_link.push(c);
        children[p].push(j);
    }

    if let Some(cycle) = find_cycle(&parent_joint, &parent_link) {
        // Report at the joint of the cycle that comes first in the file.
        let first = cycle.iter().copied().min().unwrap_or(0);
        let names: Vec<String> = cycle
            .iter()
            .map(|&j| format!("'{}'", raw.joints[j].name))
            .collect();
        let msg = format!(
            "joints {} form a cycle; a robot must be a tree",
            names.join(" → ")
        );
        return Err(map
            .error(&joint_path(first), msg)
            .about(item("joint", &raw.joints[first].name)));
    }

    let roots: Vec<usize> = (0..n_links).filter(|&l| parent_joint[l].is_none()).collect();
    let (connected, isolated): (Vec<usize>, Vec<usize>) =
        roots.iter().partition(|&&l| !children[l].is_empty());
    if connected.len() > 1 {
        let names: Vec<String> = connected
            .iter()
            .map(|&l| format!("'{}'", raw.links[l].name))
            .collect();
        let second = connected[1];
        let msg = format!(
            "several root links (links without a parent joint): {}; a robot must be one tree",
            names.join(", ")
        );
        return Err(map
            .error(&link_path(second), msg)
            .about(item("link", &raw.links[second].name)));
    }
    let root = match (connected.first(), isolated.as_slice()) {
        (Some(&r), []) => r,
        (None, [only]) => *only,
        (Some(_), [lonely, ..]) | (None, [_, lonely, ..]) => {
            let msg = "is not connected to any joint (disconnected from the tree)";
            return Err(map
                .error(&link_path(*lonely), msg)
                .about(item("link", &raw.links[*lonely].name)));
        }
        // Without cycles every link leads up to a root, so there is at least one.
        (None, []) => return Err(DescriptionError::new(&map.file, "the robot has no root link")),
    };

    let (joint_order, link_order) = depth_first(root, &children, &child_link);
    Ok(Topology {
        root,
        parent_link,
        child_link,
        children,
        joint_order,
        link_order,
        link_by_name,
        joint_by_name,
    })
}

/// Name → index; a name used twice is an error at its second use.
fn unique_names<'a>(
    names: impl Iterator<Item = &'a str>,
    kind: &str,
    path: fn(usize) -> String,
    map: &SourceMap,
) -> Result<HashMap<String, usize>, DescriptionError> {
    let mut index = HashMap::new();
    for (i, name) in names.enumerate() {
        if let Some(&first) = index.get(name) {
            let first_at = map
                .locate(&path(first))
                .map(|l| format!(" (first defined at {l})"))
                .unwrap_or_default();
            let msg = format!("duplicate {kind} name{first_at}");
            return Err(map.error(&path(i), msg).about(item(kind, name)));
        }
        index.insert(name.to_owned(), i);
    }
    Ok(index)
}

/// A cycle of joints, if the parent relation has one: each link has at most one parent joint,
/// so following parents from any link either reaches a root or runs into a loop.
fn find_cycle(parent_joint: &[Option<usize>], parent_link: &[usize]) -> Option<Vec<usize>> {
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        New,
        OnPath,
        Done,
    }
    let mut state = vec![State::New; parent_joint.len()];
    for start in 0..parent_joint.len() {
        let mut path = Vec::new();
        let mut link = start;
        while state[link] == State::New {
            state[link] = State::OnPath;
            path.push(link);
            match parent_joint[link] {
                Some(j) => link = parent_link[j],
                None => break,
            }
        }
        if state[link] == State::OnPath && parent_joint[link].is_some() {
            if let Some(pos) = path.iter().position(|&l| l == link) {
                // Joints from the top of the loop down: parent joint of each link, reversed.
                let mut cycle: Vec<usize> = path[pos..].iter().filter_map(|&l| parent_joint[l]).collect();
                cycle.reverse();
                return Some(cycle);
            }
        }
        for l in path {
            state[l] = State::Done;
        }
    }
    None
}

/// Pre-order walk from the root (iterative: a long chain must not overflow the stack).
fn depth_first(root: usize, children: &[Vec<usize>], child_link: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut joints = Vec::new();
    let mut links = vec![root];
    let mut stack: Vec<usize> = children[root].iter().rev().copied().collect();
    while let Some(j) = stack.pop() {
        joints.push(j);
        let c = child_link[j];
        links.push(c);
        stack.extend(children[c].iter().rev());
    }
    (joints, links)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::raw::{RawJoint, RawLink};
    use std::path::Path;

    fn robot(links: &[&str], joints: &[(&str, &str, &str)]) -> RawRobot {
        RawRobot {
            name: Some("r".into()),
            links: links
                .iter()
                .map(|n| RawLink {
                    name: (*n).into(),
                    inertial: None,
                })
                .collect(),
            joints: joints
                .iter()
                .map(|(n, p, c)| RawJoint {
                    name: (*n).into(),
                    kind: "revolute".into(),
                    parent: (*p).into(),
                    child: (*c).into(),
                    xyz: [0.0; 3],
                    rpy: [0.0; 3],
                    axis: [0.0, 0.0, 1.0],
                    limit: None,
                    mimic: None,
                    dynamics: Default::default(),
                })
                .collect(),
        }
    }

    fn topo(r: &RawRobot) -> Result<Topology, String> {
        topology(r, &SourceMap::new(Path::new("t"))).map_err(|e| e.to_string())
    }

    #[test]
    fn depth_first_with_children_in_file_order() {
        // b0 has two branches: a (joints ja1, ja2) listed first, then c.
        let r = robot(
            &["c1", "b0", "a1", "a2"],
            &[("jc", "b0", "c1"), ("ja1", "b0", "a1"), ("ja2", "a1", "a2")],
        );
        let t = topo(&r).unwrap();
        assert_eq!(t.root, 1);
        assert_eq!(t.joint_order, vec![0, 1, 2]);
        let r = robot(
            &["b0", "a1", "a2", "c1"],
            &[("ja1", "b0", "a1"), ("jc", "b0", "c1"), ("ja2", "a1", "a2")],
        );
        assert_eq!(topo(&r).unwrap().joint_order, vec![0, 2, 1]);
    }

    #[test]
    fn cycle_is_found_even_without_a_root() {
        let r = robot(
            &["a", "b", "c"],
            &[("j1", "a", "b"), ("j2", "b", "c"), ("j3", "c", "a")],
        );
        let e = topo(&r).unwrap_err();
        assert!(e.contains("cycle") && e.contains("joint 'j1'"), "{e}");
    }
}
