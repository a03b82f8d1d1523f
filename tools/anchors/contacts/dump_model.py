#!/usr/bin/env python3
"""Writes the Pinocchio models of the contacts anchor as text, build/models/<robot>.txt, which
bench_contacts reads back into a header-only Pinocchio built with -march=native (why text:
../common/model_text.py). The floating-cg anchor reads the same models (its build.sh runs this
script).

The models are those of tools/floating_fixtures.py (`build_model`): the URDF committed under
codegen/tests/data/example-robot-data/ on a free flyer, links joined by fixed joints merged,
quarter turns made exact as dyngen's loader takes them. Solo-12's URDF there is the one
robots/solo12.yaml reads.

bench_contacts draws each state as dyngen's bench does, a configuration in dyngen's joint
order; that is the same vector for Pinocchio only where both order the joints alike. dyngen
orders them depth-first from the root, a link's child joints in file order; Pinocchio walks the
tree urdfdom builds. This script stops when the two orders differ.

    /tmp/pinenv/bin/python dump_model.py REPO OUT_DIR [ROBOT...]   (run by build.sh)
"""

import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", ".."))  # tools/, for floating_fixtures
from model_text import dump  # noqa: E402
from floating_fixtures import ROBOTS, build_model, urdf_path  # noqa: E402

# The robots of bench_contacts.cpp and of the floating-cg anchor.
CONTACT_ROBOTS = ("solo12", "g1")


def dyngen_joint_order(path):
    """The moving joints of a URDF depth-first from its root, a link's child joints in file
    order: the order of dyngen's configuration (model/src/description/tree.rs)."""
    root = ET.parse(path).getroot()
    children, child_links = {}, set()
    for joint in root.findall("joint"):
        children.setdefault(joint.find("parent").get("link"), []).append(joint)
        child_links.add(joint.find("child").get("link"))
    (base,) = [link.get("name") for link in root.findall("link") if link.get("name") not in child_links]
    order, stack = [], list(reversed(children.get(base, [])))
    while stack:
        joint = stack.pop()
        if joint.get("type") != "fixed":
            order.append(joint.get("name"))
        stack.extend(reversed(children.get(joint.find("child").get("link"), [])))
    return order


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[2]
    robots = sys.argv[3:] or list(CONTACT_ROBOTS)
    os.makedirs(out, exist_ok=True)
    for name in robots:
        if name not in CONTACT_ROBOTS:
            sys.exit(f"unknown robot {name} ({', '.join(CONTACT_ROBOTS)})")
        robot = ROBOTS[name]
        model, _ = build_model(robot)
        pinocchio_order = list(model.names[2:])
        if pinocchio_order != dyngen_joint_order(urdf_path(robot)):
            sys.exit(f"{name}: Pinocchio orders the joints otherwise than dyngen; the anchor's "
                     f"states would not be dyngen's ({pinocchio_order})")
        with open(os.path.join(out, f"{name}.txt"), "w") as f:
            f.write(dump(model, name))
        print(f"{name}: nq {model.nq}, nv {model.nv}, {len(model.frames) - 1} frames -> {out}/{name}.txt")


if __name__ == "__main__":
    main()
