#!/usr/bin/env python3
"""Regenerate the Pinocchio reference fixtures of codegen/tests/fixtures/.

A developer tool, not run by CI. It reads the URDFs committed in robots/urdf/, builds
Pinocchio's kinematic and inertial model of each robot with the conventions dyngen uses
(fixed joints merged, panda fingers locked at 0, or kept as mimic joints) and writes, for a set of seeded random
states, every quantity the tests compare against. Field meanings and the model conventions:
codegen/tests/fixtures/README.md.

Set-up (once):

    python3 -m venv /tmp/fxenv
    /tmp/fxenv/bin/pip install -r tools/requirements.txt

Usage (from the repository root):

    /tmp/fxenv/bin/python tools/fixtures.py                      # both robots -> codegen/tests/fixtures/
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
import sys
import sysconfig
import zlib
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STATE_COUNT = 20

# Pinocchio's order of a body's ten dynamic parameters (Inertia.toDynamicParameters); the
# same order as dyngen's parameter layout.
PARAMETER_ORDER = ["m", "mc_x", "mc_y", "mc_z", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz"]

WORLD_AXES_AT_FRAME = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass(frozen=True)
class Robot:
    name: str
    urdf: str  # file name in robots/urdf/
    source: str  # where the URDF comes from (provenance, written into the fixture)
    end_effector: str  # a BODY frame of the Pinocchio model
    locked: tuple  # joints welded at 0 before anything is computed
    # URDF mimic joints as Pinocchio 4's mimic joints (`buildModelFromUrdf(..., mimic=True)`):
    # the coordinates are the joints that mimic nothing.
    mimic: bool = False
    directory: str = "robots/urdf"  # where `urdf` is, relative to the repository


ROBOTS = {
    r.name: r
    for r in [
        Robot(
            "panda",
            "panda.urdf",
            "example-robot-data/robots/panda_description/urdf/panda.urdf",
            "panda_hand_tcp",
            ("panda_finger_joint1", "panda_finger_joint2"),
        ),
        Robot(
            "ur5",
            "ur5_robot.urdf",
            "example-robot-data/robots/ur_description/urdf/ur5_robot.urdf",
            "tool0",
            (),
        ),
        # The Panda with its fingers free: panda_finger_joint2 mimics panda_finger_joint1.
        Robot(
            "panda_mimic",
            "panda.urdf",
            "example-robot-data/robots/panda_description/urdf/panda.urdf",
            "panda_hand_tcp",
            (),
            mimic=True,
        ),
        # Revolute mimic joints with multiplier 1.5 and offset 0.3, and -1 and 0.2.
        Robot(
            "mimic_arm",
            "mimic_arm.urdf",
            None,
            "tool",
            (),
            mimic=True,
            directory="codegen/tests/data/mimic",
        ),
    ]
}


# ---------------------------------------------------------------------------------------------
# model


def build_model(robot):
    """Pinocchio model without geometry; locked joints welded at q = 0.

    `buildModelFromUrdf` already merges links joined by fixed joints into the body of the
    moving joint that carries them. Without `mimic=True` the second panda finger is an
    ordinary joint, so both fingers are locked like any other joint."""
    model = pin.buildModelFromUrdf(urdf_path(robot), mimic=robot.mimic)
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
    return model, frame


def urdf_path(robot):
    return os.path.join(REPO, robot.directory, robot.urdf)


def is_mimic(model, j):
    return model.joints[j].shortname() == "JointModelMimic"


def coupling(model):
    """The tree of a mimic model (every joint, one coordinate each, as Pinocchio builds the same
    URDF without `mimic=True`) and the map from the coordinates: `q_tree = G q + o`. Pinocchio
    numbers the joints of both models alike, so tree joint j is joint j + 1 of both."""
    n_tree = model.njoints - 1
    G = np.zeros((n_tree, model.nv))
    o = np.zeros(n_tree)
    for j in joints_in_order(model):
        joint = model.joints[j]
        G[j - 1, joint.idx_v] = joint.extract().scaling if is_mimic(model, j) else 1.0
        o[j - 1] = joint.extract().offset if is_mimic(model, j) else 0.0
    return G, o


def check_provenance(robot):
    """Warn when the committed URDF differs from example-robot-data's copy (the fixtures say
    which file they come from)."""
    if robot.source is None:
        return
    share = os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix", "share")
    original = os.path.join(share, robot.source)
    committed = urdf_path(robot)
    if not os.path.exists(original):
        print(f"  note: {original} not found; provenance not checked")
        return
    with open(original, "rb") as a, open(committed, "rb") as b:
        if a.read() != b.read():
            print(f"  warning: robots/urdf/{robot.urdf} differs from {robot.source}")


def joints_in_order(model):
    return range(1, model.njoints)  # 0 is the universe


def parameters(model):
    return np.concatenate([model.inertias[j].toDynamicParameters() for j in joints_in_order(model)])


def pose(m):
    return {"translation": m.translation.tolist(), "rotation": m.rotation.tolist()}


def describe_joint(model, j, tree=None):
    """A mimic joint is described by its joint of `tree` (the model without mimic joints) and
    the joint it follows."""
    if tree is not None and is_mimic(model, j):
        mimic = model.joints[j].extract()
        master = next(k for k in joints_in_order(model) if model.joints[k].idx_v == mimic.idx_v and not is_mimic(model, k))
        described = describe_joint(tree, j)
        described["mimic"] = {"joint": model.names[master], "multiplier": mimic.scaling, "offset": mimic.offset}
        return described
    joint = model.joints[j]
    data = joint.createData()
    joint.calc(data, pin.neutral(model))
    subspace = np.asarray(data.S).reshape(6)  # [linear; angular] in the joint frame
    revolute = bool(np.any(subspace[3:]))
    return {
        "name": model.names[j],
        "type": joint.shortname(),
        "parent": model.names[model.parents[j]],
        "placement": pose(model.jointPlacements[j]),
        "axis": (subspace[3:] if revolute else subspace[:3]).tolist(),
        "kind": "revolute" if revolute else "prismatic",
        "continuous": joint.nq == 2,
    }


def describe_body(model, j):
    inertia = model.inertias[j]
    return {
        "joint": model.names[j],
        "mass": inertia.mass,
        "com": inertia.lever.tolist(),
        "inertia_about_com": inertia.inertia.tolist(),
    }


# ---------------------------------------------------------------------------------------------
# states


def seed_of(robot):
    """One seed per robot, from its name: regenerating one robot does not move the other."""
    return zlib.crc32(robot.name.encode())


def draw_state(model, rng):
    """q uniform within the joint limits (within [-π, π] for continuous joints and ranges wider
    than a turn), v and vr uniform in [-2, 2], a and ar in [-5, 5]; drawn in this order."""
    q = np.empty(model.nv)
    for j in joints_in_order(model):
        joint = model.joints[j]
        if joint.nv == 0:
            continue  # a mimic joint: its master's coordinate
        lower, upper = -math.pi, math.pi
        if joint.nq == 1:
            lo = model.lowerPositionLimit[joint.idx_q]
            hi = model.upperPositionLimit[joint.idx_q]
            if hi - lo <= 2 * math.pi:
                lower, upper = lo, hi
        q[joint.idx_v] = rng.uniform(lower, upper)
    v = rng.uniform(-2, 2, model.nv)
    a = rng.uniform(-5, 5, model.nv)
    vr = rng.uniform(-2, 2, model.nv)
    ar = rng.uniform(-5, 5, model.nv)
    return q, v, a, vr, ar


def symmetric_from_upper(m):
    """Pinocchio's crba and computeMinverse fill the upper triangle only."""
    upper = np.triu(m)
    return upper + np.triu(upper, 1).T


# ---------------------------------------------------------------------------------------------
# quantities


def evaluate(model, frame, pi, q, v, a, vr, ar, tree=None):
    """Every field of one state. q is one coordinate per joint (an angle for continuous
    joints); Pinocchio's configuration stores a continuous joint as (cos, sin).

    With mimic joints, `tree` is the same URDF without them. Pinocchio 4.1 computes D, g, tau,
    J and the pose on the mimic model itself. It refuses the regressor, aba, Minv and the
    derivatives on mimic models, and its Coriolis matrix and Jacobian time variation there are
    wrong (D a + C v + g differs from its own rnea, by up to 1.7 N·m on mimic_arm, and Jdot from
    differences of its own J by up to 3.9): those come from the tree through the coupling
    (C = Gᵀ C_tree G, Jdot = Jdot_tree G, Y = Gᵀ Y_tree, derivatives Gᵀ ∂τ_tree G at
    q_tree = G q + o, v_tree = G v, a_tree = G a), and from Pinocchio's own D (aba solves
    D a = tau − rnea(q, v, 0), Minv = D⁻¹)."""
    data = model.createData()
    q_pin = pin.integrate(model, pin.neutral(model), q)
    if tree is not None:
        G, o = coupling(model)
        t_data = tree.createData()
        q_tree = pin.integrate(tree, pin.neutral(tree), G @ q + o)

    D = symmetric_from_upper(pin.crba(model, data, q_pin))
    C = pin.computeCoriolisMatrix(model, data, q_pin, v).copy()
    g = pin.computeGeneralizedGravity(model, data, q_pin).copy()
    tau = pin.rnea(model, data, q_pin, v, a).copy()
    if tree is None:
        Y = pin.computeJointTorqueRegressor(model, data, q_pin, v, a).copy()

    pin.computeJointJacobians(model, data, q_pin)
    J = pin.getFrameJacobian(model, data, frame, WORLD_AXES_AT_FRAME).copy()
    pin.computeJointJacobiansTimeVariation(model, data, q_pin, v)
    Jdot = pin.getFrameJacobianTimeVariation(model, data, frame, WORLD_AXES_AT_FRAME).copy()
    if tree is not None:
        t_frame = tree.getFrameId(model.frames[frame].name, pin.FrameType.BODY)
        pin.computeJointJacobiansTimeVariation(tree, t_data, q_tree, G @ v)
        Jdot = pin.getFrameJacobianTimeVariation(tree, t_data, t_frame, WORLD_AXES_AT_FRAME) @ G
    pin.forwardKinematics(model, data, q_pin)
    ee = pin.updateFramePlacement(model, data, frame)

    if tree is None:
        aba = pin.aba(model, data, q_pin, v, tau).copy()
        Minv = symmetric_from_upper(pin.computeMinverse(model, data, q_pin))
        dtau_dq, dtau_dv, _ = (m.copy() for m in pin.computeRNEADerivatives(model, data, q_pin, v, a))
        dqdd_dq, dqdd_dv, _ = (m.copy() for m in pin.computeABADerivatives(model, data, q_pin, v, tau))
    else:
        Y = G.T @ pin.computeJointTorqueRegressor(tree, t_data, q_tree, G @ v, G @ a)
        C = G.T @ pin.computeCoriolisMatrix(tree, t_data, q_tree, G @ v) @ G
        # The tree through the coupling is Pinocchio's mimic model (its own check of G).
        D_tree = symmetric_from_upper(pin.crba(tree, t_data, q_tree))
        assert np.abs(G.T @ D_tree @ G - D).max() < 1e-12 * (1.0 + np.abs(D).max())
        assert np.abs(G.T @ pin.rnea(tree, t_data, q_tree, G @ v, G @ a) - tau).max() < 1e-9 * (1.0 + np.abs(tau).max())
        aba = np.linalg.solve(D, tau - pin.rnea(model, data, q_pin, v, 0 * v))
        Minv = np.linalg.inv(D)
        Minv = (Minv + Minv.T) / 2
        def coupled_rnea_derivatives(acceleration):
            d_q, d_v, _ = pin.computeRNEADerivatives(tree, t_data, q_tree, G @ v, G @ acceleration)
            return G.T @ d_q @ G, G.T @ d_v @ G

        dtau_dq, dtau_dv = coupled_rnea_derivatives(a)
        at_aba_dq, at_aba_dv = coupled_rnea_derivatives(aba)
        dqdd_dq, dqdd_dv = -Minv @ at_aba_dq, -Minv @ at_aba_dv

    # The identities the fixtures promise; a failure here means the model or a call is wrong.
    scale = 1.0 + np.abs(tau).max()
    assert np.abs(D @ a + C @ v + g - tau).max() < 1e-9 * scale
    assert np.abs(Y @ pi - tau).max() < 1e-9 * scale
    assert np.abs(aba - a).max() < 1e-8 * (1.0 + np.abs(a).max())
    assert np.abs(Minv @ D - np.eye(model.nv)).max() < 1e-8

    return {
        "q": q.tolist(),
        "q_pinocchio": q_pin.tolist(),
        "v": v.tolist(),
        "a": a.tolist(),
        "vr": vr.tolist(),
        "ar": ar.tolist(),
        "D": D.tolist(),
        "C": C.tolist(),
        "g": g.tolist(),
        "tau": tau.tolist(),
        "tau_ref": (D @ ar + C @ vr + g).tolist(),
        "J": J.tolist(),
        "Jdot": Jdot.tolist(),
        "ee_translation": ee.translation.tolist(),
        "ee_rotation": ee.rotation.tolist(),
        "Y": Y.tolist(),
        "aba": aba.tolist(),
        "Minv": Minv.tolist(),
        "dtau_dq": dtau_dq.tolist(),
        "dtau_dv": dtau_dv.tolist(),
        "dqdd_dq": dqdd_dq.tolist(),
        "dqdd_dv": dqdd_dv.tolist(),
    }


def fixture(robot, given_states=None):
    model, frame = build_model(robot)
    tree = pin.buildModelFromUrdf(urdf_path(robot)) if robot.mimic else None
    pi = parameters(model)
    if given_states is None:
        rng = np.random.default_rng(seed_of(robot))
        states = [draw_state(model, rng) for _ in range(STATE_COUNT)]
    else:
        keys = ("q", "v", "a", "vr", "ar")
        states = [tuple(np.array(s[k], dtype=float) for k in keys) for s in given_states]
    ee = model.frames[frame]
    return {
        "robot": robot.name,
        "urdf": robot.urdf,
        "urdf_path": robot.source,
        "pinocchio_version": pin.__version__,
        "locked_joints": list(robot.locked),
        "locked_at": 0.0,
        "nq": model.nq,
        "nv": model.nv,
        "joint_names": [model.names[j] for j in joints_in_order(model) if not is_mimic(model, j)],
        "joints": [describe_joint(model, j, tree) for j in joints_in_order(model)],
        "ee_frame": robot.end_effector,
        "ee_parent_joint": model.names[ee.parentJoint],
        "ee_placement_in_parent_joint": pose(ee.placement),
        "gravity": model.gravity.linear.tolist(),
        "param_order": PARAMETER_ORDER,
        "pi": pi.tolist(),
        "bodies": [describe_body(model, j) for j in joints_in_order(model)],
        "states": [evaluate(model, frame, pi, *s, tree=tree) for s in states],
    }


# ---------------------------------------------------------------------------------------------
# output


def to_json(value, depth=0):
    """Indented JSON (one space per level) with every list of numbers on one line, so a matrix
    reads as one row per line. Floats are written in Python's shortest round-trip form."""
    pad = " " * (depth + 1)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f"{pad}{json.dumps(k)}: {to_json(v, depth + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + " " * depth + "}"
    if isinstance(value, list):
        if all(not isinstance(v, (dict, list)) for v in value):
            return "[" + ", ".join(json.dumps(v) for v in value) + "]"
        items = [pad + to_json(v, depth + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + " " * depth + "]"
    return json.dumps(value)


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
