//! URDF (XML) → the raw link/joint graph, with the place of every element.
//!
//! Read with a plain XML tree rather than a URDF crate on purpose: every number must parse
//! completely (a stray `1,5` must not become `1`), a missing `<limit>` must not become
//! `[0, 0]`, and every message needs the line of its element. Only the kinematic and
//! inertial elements are read; visuals, collisions, transmissions and plugins are skipped.
//! Following urdfdom: `<limit>` `lower`/`upper` default to 0, `effort` and `velocity` are
//! required, `<axis>` defaults to `1 0 0`, `<origin>` to identity.

use super::error::{item, DescriptionError, Location};
use super::raw::{RawDynamics, RawInertial, RawJoint, RawLimit, RawLink, RawMimic, RawRobot};
use super::source_map::{joint_path, link_path, SourceMap};
use roxmltree::{Document, Node};
use std::path::Path;

/// Parses URDF text. `file` is used in messages only.
pub(crate) fn read(text: &str, file: &Path) -> Result<(RawRobot, SourceMap)> {
    let doc = Document::parse(text).map_err(|e| syntax_error(file, &e))?;
    let mut reader = Reader {
        doc: &doc,
        map: SourceMap::new(file),
        line_starts: std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect(),
    };
    let robot = reader.robot()?;
    Ok((robot, reader.map))
}

fn syntax_error(file: &Path, e: &roxmltree::Error) -> DescriptionError {
    let pos = e.pos();
    let text = e.to_string();
    // roxmltree appends " at row:col"; the place goes in front instead.
    let message = text.strip_suffix(&format!(" at {pos}")).unwrap_or(&text);
    DescriptionError::new(file, format!("XML syntax error: {message}")).at(Some(Location {
        line: pos.row as usize,
        column: pos.col as usize,
    }))
}

struct Reader<'d, 'input> {
    doc: &'d Document<'input>,
    map: SourceMap,
    /// Byte offset of each line's start: places are found in O(log n + line length), not by
    /// counting from the top of the file (`text_pos_at`), which made large files quadratic.
    line_starts: Vec<usize>,
}

type Result<T> = std::result::Result<T, DescriptionError>;

impl<'d, 'input> Reader<'d, 'input> {
    /// Line and column (in characters) of a byte offset, counted from 1 as roxmltree does.
    fn location(&self, pos: usize) -> Location {
        let text = self.doc.input_text();
        let mut pos = pos.min(text.len());
        while !text.is_char_boundary(pos) {
            pos -= 1;
        }
        let line = self.line_starts.partition_point(|&start| start <= pos);
        let start = self.line_starts[line - 1];
        Location {
            line,
            column: text[start..pos].chars().count() + 1,
        }
    }

    fn error(&self, node: Node<'_, '_>, item: Option<&str>, message: impl Into<String>) -> DescriptionError {
        let e = DescriptionError::new(&self.map.file, message).at(Some(self.location(node.range().start)));
        match item {
            Some(i) => e.about(i),
            None => e,
        }
    }

    fn record(&mut self, path: String, node: Node<'_, '_>) {
        let loc = self.location(node.range().start);
        self.map.insert(path, loc);
    }

    fn robot(&mut self) -> Result<RawRobot> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "robot" {
            let tag = root.tag_name().name();
            return Err(self.error(root, None, format!("root element is <{tag}>, expected <robot>")));
        }
        if let Some(x) = self.doc.descendants().find(|n| n.is_element() && is_xacro(n)) {
            let tag = x.tag_name().name();
            return Err(self.error(
                x,
                None,
                format!("<xacro:{tag}> found: this is a xacro file; expand it with `xacro` first"),
            ));
        }
        let mut robot = RawRobot {
            name: root
                .attribute("name")
                .filter(|n| !n.is_empty())
                .map(str::to_owned),
            ..RawRobot::default()
        };
        for node in root.children().filter(Node::is_element) {
            match node.tag_name().name() {
                "link" => {
                    let i = robot.links.len();
                    robot.links.push(self.link(node, i)?);
                }
                "joint" => {
                    let i = robot.joints.len();
                    robot.joints.push(self.joint(node, i)?);
                }
                _ => {}
            }
        }
        Ok(robot)
    }

    fn link(&mut self, node: Node<'_, '_>, i: usize) -> Result<RawLink> {
        let path = link_path(i);
        self.record(path.clone(), node);
        let name = self.name(node, "link")?;
        let it = item("link", &name);
        let it = Some(it.as_str());
        let inertial = match self.unique_child(node, "inertial", it)? {
            None => None,
            Some(inode) => {
                let ipath = format!("{path}.inertial");
                self.record(ipath.clone(), inode);
                let (xyz, rpy) = self.origin(inode, &ipath, it)?;
                let mass_node = self
                    .unique_child(inode, "mass", it)?
                    .ok_or_else(|| self.error(inode, it, "<inertial> has no <mass>"))?;
                self.record(format!("{ipath}.mass"), mass_node);
                let mass = self.required_number(mass_node, "value", it)?;
                let inertia_node = self
                    .unique_child(inode, "inertia", it)?
                    .ok_or_else(|| self.error(inode, it, "<inertial> has no <inertia>"))?;
                self.record(format!("{ipath}.inertia"), inertia_node);
                let mut inertia = [0.0; 6];
                for (slot, attr) in inertia.iter_mut().zip(["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]) {
                    *slot = self.required_number(inertia_node, attr, it)?;
                }
                Some(RawInertial {
                    xyz,
                    rpy,
                    mass,
                    inertia,
                })
            }
        };
        Ok(RawLink { name, inertial })
    }

    fn joint(&mut self, node: Node<'_, '_>, i: usize) -> Result<RawJoint> {
        let path = joint_path(i);
        self.record(path.clone(), node);
        let name = self.name(node, "joint")?;
        let label = item("joint", &name);
        let it = Some(label.as_str());
        let kind = match node.attribute_node("type") {
            Some(a) => {
                let loc = self.location(a.range().start);
                self.map.insert(format!("{path}.type"), loc);
                a.value().to_owned()
            }
            None => return Err(self.error(node, it, "<joint> has no `type` attribute")),
        };
        let parent = self.link_ref(node, "parent", &path, it)?;
        let child = self.link_ref(node, "child", &path, it)?;
        let (xyz, rpy) = self.origin(node, &path, it)?;
        let axis = match self.unique_child(node, "axis", it)? {
            None => [1.0, 0.0, 0.0],
            Some(a) => {
                self.record(format!("{path}.axis"), a);
                self.vec3(a, "xyz", it)?.unwrap_or([1.0, 0.0, 0.0])
            }
        };
        let limit = match self.unique_child(node, "limit", it)? {
            None => None,
            Some(l) => {
                self.record(format!("{path}.limit"), l);
                Some(RawLimit {
                    lower: self.number(l, "lower", it)?.unwrap_or(0.0),
                    upper: self.number(l, "upper", it)?.unwrap_or(0.0),
                    velocity: self.required_number(l, "velocity", it)?,
                    effort: self.required_number(l, "effort", it)?,
                })
            }
        };
        let mimic = match self.unique_child(node, "mimic", it)? {
            None => None,
            Some(m) => {
                self.record(format!("{path}.mimic"), m);
                let joint = m
                    .attribute("joint")
                    .ok_or_else(|| self.error(m, it, "<mimic> has no `joint` attribute"))?;
                Some(RawMimic {
                    joint: joint.to_owned(),
                    multiplier: self.number(m, "multiplier", it)?.unwrap_or(1.0),
                    offset: self.number(m, "offset", it)?.unwrap_or(0.0),
                })
            }
        };
        // `<dynamics damping friction>`: viscous (N·m·s/rad) and Coulomb (N·m) friction, the
        // meaning Gazebo and ROS give them. URDF has no armature or offset.
        let dynamics = match self.unique_child(node, "dynamics", it)? {
            None => RawDynamics::default(),
            Some(d) => {
                self.record(format!("{path}.dynamics"), d);
                RawDynamics {
                    viscous: self.number(d, "damping", it)?,
                    coulomb: self.number(d, "friction", it)?,
                    ..RawDynamics::default()
                }
            }
        };
        Ok(RawJoint {
            name,
            kind,
            parent,
            child,
            xyz,
            rpy,
            axis,
            limit,
            mimic,
            dynamics,
        })
    }

    /// The `name` attribute of a `<link>` or `<joint>`; it must be present and non-empty.
    fn name(&self, node: Node<'_, '_>, tag: &str) -> Result<String> {
        match node.attribute("name") {
            Some(n) if !n.is_empty() => Ok(n.to_owned()),
            _ => Err(self.error(node, None, format!("<{tag}> has no `name` attribute"))),
        }
    }

    /// `<parent link="..."/>` or `<child link="..."/>`.
    fn link_ref(&mut self, node: Node<'_, '_>, tag: &str, path: &str, it: Option<&str>) -> Result<String> {
        let Some(n) = self.unique_child(node, tag, it)? else {
            return Err(self.error(node, it, format!("<joint> has no <{tag}>")));
        };
        self.record(format!("{path}.{tag}"), n);
        match n.attribute("link") {
            Some(l) if !l.is_empty() => Ok(l.to_owned()),
            _ => Err(self.error(n, it, format!("<{tag}> has no `link` attribute"))),
        }
    }

    /// The `<origin>` child of `node` (xyz, rpy), identity when absent.
    fn origin(&mut self, node: Node<'_, '_>, path: &str, it: Option<&str>) -> Result<([f64; 3], [f64; 3])> {
        let Some(o) = self.unique_child(node, "origin", it)? else {
            return Ok(([0.0; 3], [0.0; 3]));
        };
        self.record(format!("{path}.origin"), o);
        if o.has_attribute("quat_xyzw") {
            return Err(self.error(
                o,
                it,
                "<origin quat_xyzw> is not supported; give the rotation as rpy",
            ));
        }
        let xyz = self.vec3(o, "xyz", it)?.unwrap_or([0.0; 3]);
        let rpy = self.vec3(o, "rpy", it)?.unwrap_or([0.0; 3]);
        Ok((xyz, rpy))
    }

    /// The only child element named `tag`, if any; two of them is an error (which one would
    /// count is a guess we refuse to make).
    fn unique_child<'a>(
        &self,
        node: Node<'a, 'input>,
        tag: &str,
        it: Option<&str>,
    ) -> Result<Option<Node<'a, 'input>>> {
        let mut found = node
            .children()
            .filter(|c| c.is_element() && c.tag_name().name() == tag);
        let first = found.next();
        if let Some(second) = found.next() {
            let parent = node.tag_name().name();
            return Err(self.error(second, it, format!("<{parent}> has more than one <{tag}>")));
        }
        Ok(first)
    }

    fn attr_location(&self, node: Node<'_, '_>, attr: &str) -> Location {
        let pos = node
            .attribute_node(attr)
            .map_or(node.range().start, |a| a.range().start);
        self.location(pos)
    }

    fn number(&self, node: Node<'_, '_>, attr: &str, it: Option<&str>) -> Result<Option<f64>> {
        let Some(text) = node.attribute(attr) else {
            return Ok(None);
        };
        match text.trim().parse::<f64>() {
            Ok(v) => Ok(Some(v)),
            Err(_) => {
                let tag = node.tag_name().name();
                let e = self.error(node, it, format!("<{tag}> {attr}=\"{text}\" is not a number"));
                Err(e.at(Some(self.attr_location(node, attr))))
            }
        }
    }

    fn required_number(&self, node: Node<'_, '_>, attr: &str, it: Option<&str>) -> Result<f64> {
        self.number(node, attr, it)?.ok_or_else(|| {
            let tag = node.tag_name().name();
            self.error(node, it, format!("<{tag}> has no `{attr}` attribute"))
        })
    }

    /// Three numbers separated by white space, e.g. `xyz="0 0 0.333"`.
    fn vec3(&self, node: Node<'_, '_>, attr: &str, it: Option<&str>) -> Result<Option<[f64; 3]>> {
        let Some(text) = node.attribute(attr) else {
            return Ok(None);
        };
        let parsed: Vec<f64> = text.split_whitespace().map_while(|t| t.parse().ok()).collect();
        let words = text.split_whitespace().count();
        match <[f64; 3]>::try_from(parsed) {
            Ok(v) if words == 3 => Ok(Some(v)),
            _ => {
                let tag = node.tag_name().name();
                let e = self.error(
                    node,
                    it,
                    format!("<{tag}> {attr}=\"{text}\" is not three numbers"),
                );
                Err(e.at(Some(self.attr_location(node, attr))))
            }
        }
    }
}

/// Whether an element belongs to xacro (by namespace, or by a literal `xacro:` prefix in a
/// document that did not declare the namespace — roxmltree rejects those, so by namespace).
fn is_xacro(node: &Node<'_, '_>) -> bool {
    node.tag_name().namespace().is_some_and(|ns| ns.contains("xacro"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_ok(text: &str) -> RawRobot {
        read(text, Path::new("t.urdf")).map(|(r, _)| r).unwrap()
    }

    fn read_err(text: &str) -> String {
        read(text, Path::new("t.urdf"))
            .map(|(r, _)| r)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn reads_links_joints_and_defaults() {
        let r = read_ok(
            r#"<robot name="r"><link name="a"/><link name="b"><inertial><mass value="2"/>
               <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
               <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>"#,
        );
        assert_eq!(r.name.as_deref(), Some("r"));
        assert_eq!(r.links.len(), 2);
        assert_eq!(r.links[1].inertial.as_ref().map(|i| i.mass), Some(2.0));
        assert_eq!(r.joints[0].axis, [1.0, 0.0, 0.0]);
        assert_eq!(r.joints[0].xyz, [0.0; 3]);
        assert_eq!(r.joints[0].limit, None);
    }

    #[test]
    fn malformed_numbers_are_errors_with_places() {
        let e = read_err(
            "<robot name=\"r\">\n<link name=\"a\"/>\n<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>\n  <origin xyz=\"0 1,5 0\"/></joint></robot>",
        );
        assert_eq!(
            e,
            "t.urdf:4:11: joint 'j': <origin> xyz=\"0 1,5 0\" is not three numbers"
        );
    }

    #[test]
    fn nan_text_parses_for_the_checks_to_reject() {
        let r = read_ok(
            r#"<robot name="r"><joint name="j" type="fixed"><parent link="a"/><child link="b"/><origin xyz="nan 0 inf"/></joint></robot>"#,
        );
        assert!(r.joints[0].xyz[0].is_nan() && r.joints[0].xyz[2].is_infinite());
    }

    #[test]
    fn xacro_is_refused() {
        let e = read_err(
            r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="a" value="1"/></robot>"#,
        );
        assert!(e.contains("xacro"), "{e}");
    }
}
