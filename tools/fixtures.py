#!/usr/bin/env python3
"""Regenerate the Pinocchio reference fixtures of codegen/tests/fixtures/.

A developer tool, not run by CI. It reads the URDFs committed in robots/urdf/,
codegen/tests/data/mimic/ and codegen/tests/data/example-robot-data/, builds Pinocchio's
kinematic and inertial model of each robot with the conventions dyngen uses (fixed joints
merged, panda fingers locked at 0, or kept as mimic joints) and writes, for a set of seeded
random states, every quantity the tests compare against. Field meanings and the model
conventions: codegen/tests/fixtures/README.md. The model-level code (states, quantities, mimic
joints through their tree, JSON layout) is tools/pinocchio_reference.py, shared with
tools/sweep.py.

Set-up (once):

    python3 -m venv /tmp/fxenv
    /tmp/fxenv/bin/pip install -r tools/requirements.txt

Usage (from the repository root):

    /tmp/fxenv/bin/python tools/fixtures.py                      # every robot -> codegen/tests/fixtures/
    /tmp/fxenv/bin/python tools/fixtures.py ur5 --out /tmp/fx    # one robot, elsewhere
    /tmp/fxenv/bin/python tools/fixtures.py --states-from codegen/tests/fixtures
        # reuse the q, v, a, vr, ar of existing fixtures instead of drawing new ones
    /tmp/fxenv/bin/python tools/fixtures.py --compare codegen/tests/fixtures --out /tmp/fx
        # also report the largest relative difference per field against existing files
"""

import argparse
import json
import math
import os
import re
import sys
import sysconfig
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinocchio_reference import (
    build_models,
    describe_model,
    draw_states,
    evaluate_states,
    exact_quarter_turns,
    is_mimic,
    to_json,
)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@dataclass(frozen=True)
class Robot:
    name: str
    urdf: str  # file name in `directory`
    source: str  # where the URDF comes from (provenance, written into the fixture)
    end_effector: str  # a BODY frame of the Pinocchio model
    locked: tuple  # joints welded at 0 before anything is computed
    directory: str = "robots/urdf"  # where the committed copy is, from the repository root
    # URDF mimic joints as Pinocchio 4's mimic joints (`mimic=True`, with the tree:
    # pinocchio_reference.build_models): the coordinates are the joints that mimic nothing.
    mimic: bool = False
    # Angles within 1e-9 rad of a quarter turn made exact, as dyngen loads them with
    # `snap_angles: 1e-9` (pinocchio_reference.exact_quarter_turns). Off for the robots whose files predate it and
    # stay as they are (panda, ur5, panda_mimic, mimic_arm; only the UR5's URDF has an angle it
    # would change, and its conditioning keeps the 5e-12 difference below 1e-9).
    exact_quarter_turns: bool = True
    # dyngen's `snap_angles: <tolerance>`: `rpy` angles within it of a multiple of π/2 made
    # exact before Pinocchio reads the URDF, so that Pinocchio sees the snapped model dyngen
    # generates (panda_rounded). None: only exact_quarter_turns above.
    snap_angles: float = None
    # The committed URDF is `source` with every `rpy` number rounded to 4 decimals and a
    # leading comment (panda_rounded.urdf): check_provenance compares it as such.
    rounded: bool = False
    # States drawn (fewer for a large robot, whose regressor makes every state big).
    states: int = 20


# URDFs kept for CI from tools/sweep.py's robots (why each: their directory's README.md). The
# end-effector is the link dyngen picks for the bare URDF, so the tests load them without options.
EXAMPLE_ROBOT_DATA = "codegen/tests/data/example-robot-data"


ROBOTS = {
    r.name: r
    for r in [
        Robot(
            "panda",
            "panda.urdf",
            "example-robot-data/robots/panda_description/urdf/panda.urdf",
            "panda_hand_tcp",
            ("panda_finger_joint1", "panda_finger_joint2"),
            exact_quarter_turns=False,
        ),
        Robot(
            "ur5",
            "ur5_robot.urdf",
            "example-robot-data/robots/ur_description/urdf/ur5_robot.urdf",
            "tool0",
            (),
            exact_quarter_turns=False,
        ),
        # The Panda URDF with every `rpy` rounded to 4 decimals (1.5708), loaded as
        # robots/panda_rounded.yaml does (snap_angles: 1e-4): the quarter turns exact again,
        # the hand's yaw -0.7854 (π/4 rounded) kept.
        Robot(
            "panda_rounded",
            "panda_rounded.urdf",
            "example-robot-data/robots/panda_description/urdf/panda.urdf",
            "panda_hand_tcp",
            ("panda_finger_joint1", "panda_finger_joint2"),
            exact_quarter_turns=False,
            snap_angles=1e-4,
            rounded=True,
        ),
        # The Panda with its fingers free: panda_finger_joint2 mimics panda_finger_joint1.
        Robot(
            "panda_mimic",
            "panda.urdf",
            "example-robot-data/robots/panda_description/urdf/panda.urdf",
            "panda_hand_tcp",
            (),
            mimic=True,
            exact_quarter_turns=False,
        ),
        # Revolute mimic joints with multiplier 1.5 and offset 0.3, and -1 and 0.2.
        Robot(
            "mimic_arm",
            "mimic_arm.urdf",
            None,
            "tool",
            (),
            "codegen/tests/data/mimic",
            mimic=True,
            exact_quarter_turns=False,
        ),
        Robot(
            "asr_twodof",
            "TwoDofs.urdf",
            "example-robot-data/robots/asr_twodof_description/urdf/TwoDofs.urdf",
            "Tip",
            (),
            EXAMPLE_ROBOT_DATA + "/asr_twodof_description",
        ),
        Robot(
            "xarm7",
            "xarm7.urdf",
            "example-robot-data/robots/xarm_description/urdf/xarm7.urdf",
            "link_eef",
            (),
            EXAMPLE_ROBOT_DATA + "/xarm_description",
        ),
        Robot(
            "kinova",
            "kinova.urdf",
            "example-robot-data/robots/kinova_description/robots/kinova.urdf",
            "j2s6s200_end_effector",
            (),
            EXAMPLE_ROBOT_DATA + "/kinova_description",
        ),
        # Inertias that are not physical (four links break the triangle inequality by 19-20%),
        # loaded as written by both: 16 DOF, so five states keep the file small.
        Robot(
            "allegro_right_hand",
            "allegro_right_hand.urdf",
            "example-robot-data/robots/allegro_hand_description/urdf/allegro_right_hand.urdf",
            "link_3.0_tip",
            (),
            EXAMPLE_ROBOT_DATA + "/allegro_hand_description",
            states=5,
        ),
    ]
}


# ---------------------------------------------------------------------------------------------
# model


def build_model(robot):
    """Pinocchio model without geometry (pinocchio_reference.build_models), locked joints welded
    at q = 0, and the tree of a mimic model (None without mimic joints).

    Without `mimic=True` the second panda finger is an ordinary joint, so both fingers are
    locked like any other joint."""
    with open(urdf_path(robot)) as f:
        urdf = f.read()
    if robot.snap_angles is not None:
        urdf = exact_quarter_turns(urdf, robot.snap_angles)
    elif robot.exact_quarter_turns:
        urdf = exact_quarter_turns(urdf)
    model, tree = build_models(urdf, robot.mimic)
    if robot.locked and robot.mimic:
        sys.exit(f"{robot.name}: locked joints on a mimic model are not supported")
    if robot.locked:
        ids = []
        for joint in robot.locked:
            if not model.existJointName(joint):
                sys.exit(f"{robot.name}: no joint {joint!r} to lock")
            ids.append(model.getJointId(joint))
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
    if not model.existBodyName(robot.end_effector):
        sys.exit(f"{robot.name}: no body frame {robot.end_effector!r}")
    frame = model.getFrameId(robot.end_effector, pin.FrameType.BODY)
    for j in range(1, model.njoints):
        if model.joints[j].nv != 1 and not is_mimic(model, j):
            sys.exit(f"{robot.name}: joint {model.names[j]} has {model.joints[j].nv} DOF")
    return model, frame, tree


def urdf_path(robot):
    return os.path.join(REPO, robot.directory, robot.urdf)


def check_provenance(robot):
    """Warn when the committed URDF differs from example-robot-data's copy (the fixtures say
    which file they come from); a URDF written for the tests has no source."""
    if robot.source is None:
        return
    share = os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix", "share")
    original = os.path.join(share, robot.source)
    committed = urdf_path(robot)
    if not os.path.exists(original):
        print(f"  note: {original} not found; provenance not checked")
        return
    with open(original, "rb") as a, open(committed, "rb") as b:
        expected, actual = a.read(), b.read()
    if robot.rounded:
        expected, actual = rounded_rpy(expected.decode()), without_first_comment(actual.decode())
    if expected != actual:
        kind = "rounded " if robot.rounded else ""
        print(f"  warning: {robot.directory}/{robot.urdf} differs from {kind}{robot.source}")


def rounded_rpy(urdf):
    """Every number of every `rpy` attribute with 4 decimals, as `rounded()` in
    codegen/tests/suite/near_exact_angles.rs writes them (Rust's `{:.4}`)."""

    def rewrite(m):
        return f'rpy="{" ".join(f"{float(x):.4f}" for x in m.group(1).split())}"'

    return re.sub(r'rpy="([^"]*)"', rewrite, urdf)


def without_first_comment(urdf):
    """The URDF text without its first XML comment (the one saying how a derived file was made)."""
    start = urdf.index("<!--")
    end = urdf.index("-->", start) + 3
    return urdf[:start] + urdf[end:].removeprefix("\n")


def fixture(robot, given_states=None):
    model, frame, tree = build_model(robot)
    if given_states is None:
        states = draw_states(model, robot.name, robot.states)
    else:
        keys = ("q", "v", "a", "vr", "ar")
        states = [tuple(np.array(s[k], dtype=float) for k in keys) for s in given_states]
    return {
        "robot": robot.name,
        "urdf": robot.urdf,
        "urdf_path": robot.source,
        "pinocchio_version": pin.__version__,
        "locked_joints": list(robot.locked),
        "locked_at": 0.0,
        **describe_model(model, frame, tree),
        "states": evaluate_states(model, frame, states, tree),
    }


# ---------------------------------------------------------------------------------------------
# comparison with existing files


def split_leaves(value, numbers, words):
    """Numbers and everything else of a JSON value, in document order."""
    if isinstance(value, dict):
        for k, v in value.items():
            words.append(k)
            split_leaves(v, numbers, words)
    elif isinstance(value, list):
        for v in value:
            split_leaves(v, numbers, words)
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        numbers.append(float(value))
    else:
        words.append(value)


def difference(new, old):
    """max |new − old| / max(1, max |old|) over the numbers of two JSON values; infinite if
    their shapes or non-numeric content differ."""
    n_numbers, n_words, o_numbers, o_words = [], [], [], []
    split_leaves(new, n_numbers, n_words)
    split_leaves(old, o_numbers, o_words)
    if n_words != o_words or len(n_numbers) != len(o_numbers):
        return math.inf
    if not n_numbers:
        return 0.0
    a, b = np.array(n_numbers), np.array(o_numbers)
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


def largest_differences(new, old):
    """Per top-level field and per state field: the largest relative difference."""
    result = {k: difference(new[k], old.get(k)) for k in new if k != "states"}
    if len(new["states"]) != len(old["states"]):
        result["states"] = math.inf
        return result
    for key in new["states"][0]:
        pairs = [(n[key], o[key]) for n, o in zip(new["states"], old["states"]) if key in o]
        result["states[]." + key] = max(difference(n, o) for n, o in pairs) if pairs else None
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", help=f"any of {', '.join(ROBOTS)} (default: all)")
    parser.add_argument("--out", default=os.path.join(REPO, "codegen", "tests", "fixtures"))
    parser.add_argument("--states-from", metavar="DIR", help="take q, v, a, vr, ar from DIR/<robot>.json")
    parser.add_argument("--compare", metavar="DIR", help="compare the result with DIR/<robot>.json")
    args = parser.parse_args()

    unknown = [r for r in args.robots if r not in ROBOTS]
    if unknown:
        parser.error(f"unknown robot(s) {', '.join(unknown)}; known: {', '.join(ROBOTS)}")
    worst = 0.0
    for name in args.robots or list(ROBOTS):
        robot = ROBOTS[name]
        given = None
        if args.states_from:
            with open(os.path.join(args.states_from, name + ".json")) as f:
                given = json.load(f)["states"]
        check_provenance(robot)
        result = fixture(robot, given)
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, name + ".json")
        with open(path, "w") as f:
            f.write(to_json(result) + "\n")
        print(f"{path}: {result['nv']} DOF, {len(result['states'])} states")
        if args.compare:
            with open(os.path.join(args.compare, name + ".json")) as f:
                old = json.load(f)
            for key, value in largest_differences(result, old).items():
                print(f"  {key:30} {'missing' if value is None else f'{value:.1e}'}")
                if value is not None:
                    worst = max(worst, value)
    if args.compare:
        print(f"largest relative difference: {worst:.1e}")


if __name__ == "__main__":
    main()
