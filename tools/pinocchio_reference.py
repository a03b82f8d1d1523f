"""Pinocchio reference values for a robot model: what tools/fixtures.py (the committed fixtures)
and tools/sweep.py (every fixed-base URDF of example-robot-data) both write.

Given a Pinocchio model and an end-effector frame, it draws seeded random states and computes
every quantity the tests compare against, in the fields of codegen/tests/fixtures/README.md.
Conventions (frames, parameter order, matrix layout) are described there. A model with mimic
joints (Pinocchio 4's `mimic=True`) comes with its tree, the same URDF loaded without them
(`build_models`): the fields Pinocchio does not compute, or computes wrong, on a mimic model
come from the tree through the coupling (`evaluate`).
"""
import json
import math
import re
import zlib

import numpy as np
import pinocchio as pin

# Pinocchio's order of a body's ten dynamic parameters (Inertia.toDynamicParameters); the
# same order as dyngen's parameter layout.
PARAMETER_ORDER = ["m", "mc_x", "mc_y", "mc_z", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz"]

WORLD_AXES_AT_FRAME = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


# ---------------------------------------------------------------------------------------------
# model


QUARTER_TURN = math.pi / 2
RPY = re.compile(r'(\brpy\s*=\s*)(["\'])([^"\']*)\2')


def exact_quarter_turns(urdf, tolerance=None):
    """The URDF text with every `rpy` angle within 1e-9 rad of a multiple of π/2 written as
    that multiple, which is the model dyngen loads with `snap_angles: 1e-9` (what the tests of
    the example-robot-data fixtures and robots/ur5.yaml ask for; dyngen uses an angle as written
    unless asked). A URDF that writes 1.57079632679 (Kinova, UR) otherwise gives
    Pinocchio rotations 5e-12 off dyngen's, which an ill-conditioned mass matrix amplifies to
    more than 1e-9 in forward dynamics. Angles farther off (1.5708) are left alone, as
    `snap_angles: 1e-9` leaves them, unless a `tolerance` is given: then this is dyngen's
    `snap_angles: <tolerance>` (model/src/description/near_exact.rs), e.g. 1e-4 makes `1.5708` exact and
    leaves `0.7854` (π/4 rounded) as written."""

    def snap(text):
        try:
            angle = float(text)
        except ValueError:
            # Not a number: an unexpanded xacro expression, e.g. in a comment (TIAGo Pro);
            # left for the URDF reader to judge.
            return text
        k = round(angle / QUARTER_TURN)
        distance = abs(angle - k * QUARTER_TURN)
        near = distance < 1e-9 or (tolerance is not None and distance <= tolerance)
        if angle != k * QUARTER_TURN and near:
            return repr(k * QUARTER_TURN)
        return text

    def rewrite(m):
        angles = " ".join(snap(t) for t in m.group(3).split())
        return f"{m.group(1)}{m.group(2)}{angles}{m.group(2)}"

    return RPY.sub(rewrite, urdf)


def build_models(urdf, mimic=False):
    """Pinocchio's model of the URDF text `urdf` (no geometry) and, with `mimic=True`, the
    mimic model (Pinocchio 4's mimic joints: the coordinates are the joints that mimic nothing)
    and its tree, the same URDF without mimic support (every joint a coordinate); without
    mimic support the tree is None.

    `buildModelFromXML` already merges links joined by fixed joints into the body of the moving
    joint that carries them."""
    model = pin.buildModelFromXML(urdf, mimic=mimic)
    tree = pin.buildModelFromXML(urdf) if mimic else None
    return model, tree


def joints_in_order(model):
    """Every joint but the universe (0): one body each, mimic joints included."""
    return range(1, model.njoints)


def is_mimic(model, j):
    return model.joints[j].shortname() == "JointModelMimic"


def moving_joints(model):
    """The joints that have a coordinate: all of them, except mimic joints (nv = 0), which
    follow another joint."""
    return [j for j in joints_in_order(model) if not is_mimic(model, j)]


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


def parameters(model):
    return np.concatenate([model.inertias[j].toDynamicParameters() for j in joints_in_order(model)])


def pose(m):
    return {"translation": m.translation.tolist(), "rotation": m.rotation.tolist()}


def describe_joint(model, j, tree=None):
    """A mimic joint is described by its joint of `tree` (the model without mimic joints) and
    the joint it follows."""
    if is_mimic(model, j):
        if tree is None:
            raise ValueError(f"mimic joint {model.names[j]}: describing it needs the tree (build_models)")
        mimic = model.joints[j].extract()
        master = next(k for k in moving_joints(model) if model.joints[k].idx_v == mimic.idx_v)
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


def describe_model(model, frame, tree=None):
    """The model's fields of a reference file, from `nq` to `bodies`, in the file's order;
    `tree` as `build_models` gives it."""
    ee = model.frames[frame]
    return {
        "nq": model.nq,
        "nv": model.nv,
        "joint_names": [model.names[j] for j in moving_joints(model)],
        "joints": [describe_joint(model, j, tree) for j in joints_in_order(model)],
        "ee_frame": ee.name,
        "ee_parent_joint": model.names[ee.parentJoint],
        "ee_placement_in_parent_joint": pose(ee.placement),
        "gravity": model.gravity.linear.tolist(),
        "param_order": PARAMETER_ORDER,
        "pi": parameters(model).tolist(),
        "bodies": [describe_body(model, j) for j in joints_in_order(model)],
    }


# ---------------------------------------------------------------------------------------------
# states


def seed_of(name):
    """One seed per robot, from its name: regenerating one robot does not move another."""
    return zlib.crc32(name.encode())


def draw_state(model, rng):
    """q uniform within the joint limits (within [-π, π] for continuous joints and ranges wider
    than a turn), v and vr uniform in [-2, 2], a and ar in [-5, 5]; drawn in this order."""
    q = np.empty(model.nv)
    for j in moving_joints(model):
        joint = model.joints[j]
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


def draw_states(model, name, count):
    rng = np.random.default_rng(seed_of(name))
    return [draw_state(model, rng) for _ in range(count)]


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

    # The identities the reference values promise; a failure here means the model or a call
    # is wrong.
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


def evaluate_states(model, frame, states, tree=None):
    pi = parameters(model)
    return [evaluate(model, frame, pi, *s, tree=tree) for s in states]


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
