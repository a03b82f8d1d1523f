#!/usr/bin/env python3
"""Regenerate the floating-base Pinocchio reference fixtures of codegen/tests/fixtures/floating/.

A developer tool, not run by CI. It reads the URDFs committed in
codegen/tests/data/example-robot-data/, builds Pinocchio's model of each robot on a free-flying
root joint (`pin.JointModelFreeFlyer()`, named `root_joint`; fixed joints merged into bodies)
and writes, for a set of seeded random states, every quantity the tests compare against:
dynamics, derivatives, centroidal quantities, energies, named frames, and the configuration
space's integrate/difference. Field meanings and conventions: codegen/tests/fixtures/README.md
("Floating bases"). A robot with mimic joints is loaded with `mimic=True` too; its values come
from the tree (the same URDF without mimic support) carried through the coupling, checked
against what Pinocchio computes on the mimic model itself (`evaluate_mimic`). Helpers shared with the fixed-base fixtures (quarter turns made exact,
joint and body descriptions, parameters, JSON layout) come from tools/pinocchio_reference.py.
Before writing, it checks every state against identities and finite differences and stops at
the first failure; it prints the worst residual of each check.

Set-up (once):

    python3 -m venv /tmp/fxenv
    /tmp/fxenv/bin/pip install -r tools/requirements.txt

Usage (from the repository root):

    /tmp/fxenv/bin/python tools/floating_fixtures.py                  # every robot -> codegen/tests/fixtures/floating/
    /tmp/fxenv/bin/python tools/floating_fixtures.py g1 --out /tmp/fx  # one robot, elsewhere

Run twice, it writes byte-identical files.
"""

import argparse
import math
import os
import sys
import sysconfig
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pinocchio_reference import (
    PARAMETER_ORDER,
    describe_body,
    describe_joint,
    exact_quarter_turns,
    is_mimic,
    parameters,
    pose,
    seed_of,
    symmetric_from_upper,
    to_json,
)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE_ROBOT_DATA = "codegen/tests/data/example-robot-data"

ROOT_JOINT = "root_joint"  # the name Pinocchio gives the free flyer
LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
LOCAL = pin.ReferenceFrame.LOCAL

BASE_POSITION_RANGE = 1.0  # m, each coordinate uniform in [-1, 1]
VELOCITY_RANGE = 2.0  # v and vr uniform in [-2, 2]
ACCELERATION_RANGE = 5.0  # a and ar uniform in [-5, 5]
INTEGRATE_STEP = 0.1  # `integrate` = q ⊕ 0.1 v
FD_STEP = 1e-6  # central differences of D, J and rnea along q ⊕ ±h δ


@dataclass(frozen=True)
class Robot:
    name: str  # the fixture's name (and the seed: CRC-32 of it)
    urdf: str  # file name in `directory`
    source: str  # the file inside example-robot-data (provenance, written into the fixture)
    directory: str  # where the committed copy is, from the repository root
    frames: tuple  # BODY frames (URDF links) whose pose and Jacobians are compared
    states: int
    mimic: bool = False  # loaded with Pinocchio 4's mimic joints (`mimic=True`)


ROBOTS = {
    r.name: r
    for r in [
        # Solo-12 quadruped (ODRI): 12 revolute joints, 2.5 kg; limits ±10 rad, so drawn in
        # [-π, π] like every range wider than a turn.
        Robot(
            "solo12",
            "solo12.urdf",
            "example-robot-data/robots/solo_description/robots/solo12.urdf",
            EXAMPLE_ROBOT_DATA + "/solo_description",
            ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT", "base_link"),
            20,
        ),
        # Unitree G1 humanoid, 29 revolute joints, 33.3 kg. The feet are the ankle-roll links
        # (the URDF has no sole link), the hands the rubber hands (fixed to the wrist-yaw
        # links), and the IMU is on the base body (pelvis). Six states keep the file small.
        Robot(
            "g1",
            "g1_29dof_rev_1_0.urdf",
            "example-robot-data/robots/g1_description/urdf/g1_29dof_rev_1_0.urdf",
            EXAMPLE_ROBOT_DATA + "/g1_description",
            ("left_ankle_roll_link", "right_ankle_roll_link", "left_rubber_hand", "right_rubber_hand", "imu_in_pelvis"),
            6,
        ),
        # A torso with an arm and a two-finger gripper, written for dyngen's tests: the right
        # finger (prismatic) mimics the left with multiplier -1 and offset 0.01, a tail
        # on a branch of its own mimics the elbow (0.5, -0.2). 4 coordinates, 6 joints.
        Robot(
            "floating_gripper",
            "floating_gripper.urdf",
            None,
            "codegen/tests/data/mimic",
            ("tool", "left_finger", "right_finger", "tail", "torso"),
            10,
            mimic=True,
        ),
    ]
}


# ---------------------------------------------------------------------------------------------
# model


def urdf_path(robot):
    return os.path.join(REPO, robot.directory, robot.urdf)


def check_provenance(robot):
    """Warn when the committed URDF differs from example-robot-data's copy."""
    if robot.source is None:
        print(f"  note: {robot.urdf} is dyngen's own; no provenance to check")
        return
    share = os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix", "share")
    original = os.path.join(share, robot.source)
    if not os.path.exists(original):
        print(f"  note: {original} not found; provenance not checked")
        return
    with open(original, "rb") as a, open(urdf_path(robot), "rb") as b:
        if a.read() != b.read():
            print(f"  warning: {robot.directory}/{robot.urdf} differs from {robot.source}")


def build_model(robot, mimic=False):
    """Pinocchio's model on a free flyer (fixed joints merged), quarter turns made exact as
    dyngen's loader takes them, and the ids of the robot's frames; with `mimic`, Pinocchio 4's
    mimic joints (whose nq and nv are 0)."""
    with open(urdf_path(robot)) as f:
        urdf = exact_quarter_turns(f.read())
    model = pin.buildModelFromXML(urdf, pin.JointModelFreeFlyer(), mimic=mimic)
    if model.names[1] != ROOT_JOINT or model.joints[1].shortname() != "JointModelFreeFlyer":
        sys.exit(f"{robot.name}: joint 1 is {model.names[1]} ({model.joints[1].shortname()}), not the free flyer")
    for j in range(2, model.njoints):
        if is_mimic(model, j):
            continue
        if model.joints[j].nq != 1 or model.joints[j].nv != 1:
            sys.exit(f"{robot.name}: joint {model.names[j]} has nq {model.joints[j].nq}, nv {model.joints[j].nv}")
    frames = []
    for name in robot.frames:
        if not model.existBodyName(name):
            sys.exit(f"{robot.name}: no body frame {name!r}")
        frames.append(model.getFrameId(name, pin.FrameType.BODY))
    return model, frames


def base_body(model):
    """The root link: the BODY frame carried by the free flyer directly."""
    root_frame = model.getFrameId(ROOT_JOINT, pin.FrameType.JOINT)
    (name,) = [f.name for f in model.frames if f.type == pin.FrameType.BODY and f.parentFrame == root_frame]
    return name


def describe_model(model, frames, robot, tree=None):
    """With mimic joints, `joint_names` lists the coordinates (the joints that mimic nothing) and
    `joints` every joint of the tree (a mimic joint's entry with its `mimic`)."""
    return {
        "robot": robot.name,
        "urdf": robot.urdf,
        "urdf_path": robot.source or f"{robot.directory}/{robot.urdf}",
        "pinocchio_version": pin.__version__,
        "nq": model.nq,
        "nv": model.nv,
        "joint_names": [model.names[j] for j in range(2, model.njoints) if not is_mimic(model, j)],
        "joints": [describe_joint(model, j, tree) for j in range(2, model.njoints)],
        "base_body": base_body(model),
        "gravity": model.gravity.linear.tolist(),
        "param_order": PARAMETER_ORDER,
        "pi": parameters(model).tolist(),
        "bodies": [describe_body(model, j) for j in range(1, model.njoints)],
        "frames": [
            {
                "name": model.frames[f].name,
                "parent_joint": model.names[model.frames[f].parentJoint],
                "placement": pose(model.frames[f].placement),
            }
            for f in frames
        ],
    }


# ---------------------------------------------------------------------------------------------
# states


def draw_state(model, rng):
    """In this order: the base position uniform in [-1, 1]³, its orientation a normalised
    4-vector of standard normals (Pinocchio's order x, y, z, w), each joint uniform within its
    limits (within [-π, π] for a range wider than a turn), then v and vr uniform in [-2, 2] and
    a and ar in [-5, 5] (nv each, in the order v, a, vr, ar)."""
    position = rng.uniform(-BASE_POSITION_RANGE, BASE_POSITION_RANGE, 3)
    quaternion = rng.standard_normal(4)
    quaternion /= np.linalg.norm(quaternion)
    joints = np.empty(model.nq - 7)
    for j in range(2, model.njoints):
        if is_mimic(model, j):
            continue  # it follows its master: no coordinate of its own
        i = model.joints[j].idx_q
        lower, upper = model.lowerPositionLimit[i], model.upperPositionLimit[i]
        if upper - lower > 2 * math.pi:
            lower, upper = -math.pi, math.pi
        joints[i - 7] = rng.uniform(lower, upper)
    q = np.concatenate([position, quaternion, joints])
    v = rng.uniform(-VELOCITY_RANGE, VELOCITY_RANGE, model.nv)
    a = rng.uniform(-ACCELERATION_RANGE, ACCELERATION_RANGE, model.nv)
    vr = rng.uniform(-VELOCITY_RANGE, VELOCITY_RANGE, model.nv)
    ar = rng.uniform(-ACCELERATION_RANGE, ACCELERATION_RANGE, model.nv)
    return q, v, a, vr, ar


def draw_states(model, name, count):
    rng = np.random.default_rng(seed_of(name))
    return [draw_state(model, rng) for _ in range(count)]


# ---------------------------------------------------------------------------------------------
# quantities


class Worst:
    """The largest residual of each check, over all states (printed at the end)."""

    def __init__(self):
        self.values = {}

    def check(self, name, residual, tolerance):
        self.values[name] = max(self.values.get(name, 0.0), residual)
        assert residual < tolerance, f"{name}: {residual:.3e} ≥ {tolerance:.1e}"


def relative(error, expected):
    return float(np.abs(error).max() / (1.0 + np.abs(expected).max()))


def along(model, q, direction, h=FD_STEP):
    """q ⊕ h δ and q ⊕ −h δ."""
    return pin.integrate(model, q, h * direction), pin.integrate(model, q, -h * direction)


def frame_quantities(model, data, frames, q, v):
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    result = {}
    for f in frames:
        placement = data.oMf[f]
        result[model.frames[f].name] = {
            "translation": placement.translation.copy(),
            "rotation": placement.rotation.copy(),
            "J_lwa": pin.getFrameJacobian(model, data, f, LWA).copy(),
            "J_local": pin.getFrameJacobian(model, data, f, LOCAL).copy(),
        }
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    for f in frames:
        result[model.frames[f].name]["Jdot_lwa"] = pin.getFrameJacobianTimeVariation(model, data, f, LWA).copy()
    return result


def evaluate(model, frames, pi, q, v, a, vr, ar, q_other, worst):
    data = model.createData()
    nv = model.nv

    D = symmetric_from_upper(pin.crba(model, data, q))
    C = pin.computeCoriolisMatrix(model, data, q, v).copy()
    g = pin.computeGeneralizedGravity(model, data, q).copy()
    tau = pin.rnea(model, data, q, v, a).copy()
    Y = pin.computeJointTorqueRegressor(model, data, q, v, a).copy()
    aba = pin.aba(model, data, q, v, tau).copy()
    Minv = symmetric_from_upper(pin.computeMinverse(model, data, q))
    dtau_dq, dtau_dv, _ = (m.copy() for m in pin.computeRNEADerivatives(model, data, q, v, a))
    dqdd_dq, dqdd_dv, _ = (m.copy() for m in pin.computeABADerivatives(model, data, q, v, tau))

    com = pin.centerOfMass(model, data, q).copy()
    Jcom = pin.jacobianCenterOfMass(model, data, q).copy()
    Ag = pin.ccrba(model, data, q, v).copy()
    hg = data.hg.vector.copy()
    dAg = pin.dccrba(model, data, q, v).copy()
    dAg_v = dAg @ v
    kinetic = float(pin.computeKineticEnergy(model, data, q, v))
    potential = float(pin.computePotentialEnergy(model, data, q))
    frame_values = frame_quantities(model, data, frames, q, v)
    integrated = pin.integrate(model, q, INTEGRATE_STEP * v)
    difference = pin.difference(model, q, q_other)

    # Identities. Scales: 1 + the largest magnitude of the expected side.
    mass = sum(model.inertias[j].mass for j in range(1, model.njoints))
    worst.check("D a + C v + g = tau", relative(D @ a + C @ v + g - tau, tau), 1e-9)
    worst.check("Y pi = tau", relative(Y @ pi - tau, tau), 1e-9)
    worst.check("aba = a", relative(aba - a, a), 1e-8)
    worst.check("Minv D = 1", float(np.abs(Minv @ D - np.eye(nv)).max()), 1e-8)
    worst.check("Jcom = Ag[0:3] / m", relative(Jcom - Ag[:3] / mass, Jcom), 1e-12)
    worst.check("hg = Ag v", relative(hg - Ag @ v, hg), 1e-12)
    # The centroidal momentum's rate from Pinocchio's own function, against Ag a + dAg v.
    dhg = pin.computeCentroidalMomentumTimeVariation(model, data, q, v, a).vector.copy()
    worst.check("dhg = Ag a + dAg v", relative(Ag @ a + dAg_v - dhg, dhg), 1e-9)
    worst.check("T = v D v / 2", abs(kinetic - 0.5 * v @ D @ v) / (1.0 + kinetic), 1e-12)
    worst.check("V = -m g·com", abs(potential + mass * model.gravity.linear @ com) / (1.0 + abs(potential)), 1e-12)

    # The base rows of tau are the wrench the free joint applies to the base body, in the base
    # frame ([force; torque] about the base origin): the rate of the whole robot's momentum
    # minus gravity, from the centroidal momentum (world axes, about the centre of mass).
    wrench_at_com = dhg - np.concatenate([mass * model.gravity.linear, np.zeros(3)])
    world_at_com = pin.SE3(np.eye(3), com)
    pin.forwardKinematics(model, data, q)
    base_pose = data.oMi[1]
    base_wrench = base_pose.actInv(world_at_com.act(pin.Force(wrench_at_com))).vector
    worst.check("tau[0:6] = base wrench", relative(tau[:6] - base_wrench, tau[:6]), 1e-9)

    # (Ḋ − 2C) skew-symmetric, Ḋ by central difference along q ⊕ ±h v.
    q_plus, q_minus = along(model, q, v)
    D_dot = (symmetric_from_upper(pin.crba(model, data, q_plus)) - symmetric_from_upper(pin.crba(model, data, q_minus))) / (
        2 * FD_STEP
    )
    N = D_dot - 2 * C
    worst.check("(Ḋ − 2C) + (Ḋ − 2C)ᵀ = 0", relative(N + N.T, D_dot), 1e-6)

    # dtau_dq, dqdd_dq and the Jacobians' time variation against central differences.
    fd_dtau = np.empty((nv, nv))
    fd_dqdd = np.empty((nv, nv))
    for j in range(nv):
        plus, minus = along(model, q, np.eye(nv)[j])
        fd_dtau[:, j] = (pin.rnea(model, data, plus, v, a) - pin.rnea(model, data, minus, v, a)) / (2 * FD_STEP)
        fd_dqdd[:, j] = (pin.aba(model, data, plus, v, tau) - pin.aba(model, data, minus, v, tau)) / (2 * FD_STEP)
    worst.check("dtau_dq (central differences)", relative(dtau_dq - fd_dtau, dtau_dq), 1e-6)
    worst.check("dqdd_dq (central differences)", relative(dqdd_dq - fd_dqdd, dqdd_dq), 1e-6)
    fd_dtau_dv = np.empty((nv, nv))
    for j in range(nv):
        e = FD_STEP * np.eye(nv)[j]
        fd_dtau_dv[:, j] = (pin.rnea(model, data, q, v + e, a) - pin.rnea(model, data, q, v - e, a)) / (2 * FD_STEP)
    worst.check("dtau_dv (central differences)", relative(dtau_dv - fd_dtau_dv, dtau_dv), 1e-6)

    plus_frames = frame_quantities(model, data, frames, q_plus, v)
    minus_frames = frame_quantities(model, data, frames, q_minus, v)
    pin.forwardKinematics(model, data, q, v, a)
    for f in frames:
        name = model.frames[f].name
        values = frame_values[name]
        R = values["rotation"]
        rotate = np.kron(np.eye(2), R)
        worst.check("J_lwa = R J_local", relative(rotate @ values["J_local"] - values["J_lwa"], values["J_lwa"]), 1e-12)
        fd = (plus_frames[name]["J_lwa"] - minus_frames[name]["J_lwa"]) / (2 * FD_STEP)
        worst.check("Jdot_lwa = d/dt J_lwa (central differences)", relative(values["Jdot_lwa"] - fd, values["Jdot_lwa"]), 1e-6)
        classical = pin.getFrameClassicalAcceleration(model, data, f, LWA).vector
        worst.check(
            "J_lwa a + Jdot_lwa v = classical acceleration",
            relative(values["J_lwa"] @ a + values["Jdot_lwa"] @ v - classical, classical),
            1e-9,
        )

    # integrate and difference are inverse (orientation compared as rotations: q and -q are
    # the same one).
    back = pin.integrate(model, q, difference)
    rotation_of = lambda c: pin.Quaternion(c[6], c[3], c[4], c[5]).toRotationMatrix()  # noqa: E731
    error = np.concatenate([back[:3] - q_other[:3], (rotation_of(back) - rotation_of(q_other)).ravel(), back[7:] - q_other[7:]])
    worst.check("q ⊕ difference(q, q') = q'", relative(error, q_other), 1e-12)

    return {
        "q": q.tolist(),
        "v": v.tolist(),
        "a": a.tolist(),
        "vr": vr.tolist(),
        "ar": ar.tolist(),
        "D": D.tolist(),
        "C": C.tolist(),
        "g": g.tolist(),
        "tau": tau.tolist(),
        "tau_ref": (D @ ar + C @ vr + g).tolist(),
        "Y": Y.tolist(),
        "aba": aba.tolist(),
        "Minv": Minv.tolist(),
        "dtau_dq": dtau_dq.tolist(),
        "dtau_dv": dtau_dv.tolist(),
        "dqdd_dq": dqdd_dq.tolist(),
        "dqdd_dv": dqdd_dv.tolist(),
        "com": com.tolist(),
        "Jcom": Jcom.tolist(),
        "Ag": Ag.tolist(),
        "hg": hg.tolist(),
        "dAg_v": dAg_v.tolist(),
        "kinetic_energy": kinetic,
        "potential_energy": potential,
        "frames": {
            name: {k: values[k].tolist() for k in ("translation", "rotation", "J_lwa", "Jdot_lwa", "J_local")}
            for name, values in frame_values.items()
        },
        "integrate": integrated.tolist(),
        "difference": difference.tolist(),
    }


def coupling(model, tree):
    """`ν_tree = G ν` and `q_tree = [base; G_joints q_joints + o]` of a floating mimic model and
    its tree (Pinocchio numbers the joints of both alike): the base's six rows the identity."""
    G = np.zeros((tree.nv, model.nv))
    G[:6, :6] = np.eye(6)
    o = np.zeros(tree.nq - 7)
    for j in range(2, model.njoints):
        row = tree.joints[j].idx_v
        if is_mimic(model, j):
            mimic = model.joints[j].extract()
            G[row, mimic.idx_v] = mimic.scaling
            o[row - 6] = mimic.offset
        else:
            G[row, model.joints[j].idx_v] = 1.0
    return G, o


def evaluate_mimic(model, tree, frames, tree_frames, q, v, a, vr, ar, q_other, worst):
    """The fields of one state of a floating robot with mimic joints. Pinocchio 4.1 refuses the
    regressor, aba, Minv and the derivatives on a mimic model and its Coriolis matrix and `J̇`
    there are wrong (codegen/tests/fixtures/README.md, "Robots with mimic joints"), so every
    field comes from the tree at `(q_tree, G ν, G ν̇)` (checked by `evaluate` as any robot is)
    carried through `G`: `D = Gᵀ D_tree G`, `τ = Gᵀ τ_tree`, `Y = Gᵀ Y_tree`, `J = J_tree G`, …;
    `aba` solves `D ν̇ = τ − bias`, `Minv = D⁻¹`, and forward dynamics' derivatives are
    `−D⁻¹ ∂τ/∂x` at `ν̇ = aba`. What Pinocchio computes on the mimic model itself (`D`, `g`,
    `τ`, the frames' poses and `J`) is checked against them."""
    G, o = coupling(model, tree)

    def in_tree(c):
        return np.concatenate([c[:7], G[6:, 6:] @ c[7:] + o])

    q_tree = in_tree(q)
    t = evaluate(tree, tree_frames, parameters(tree), q_tree, G @ v, G @ a, G @ vr, G @ ar, in_tree(q_other), worst)
    arr = {k: np.array(x) for k, x in t.items() if not isinstance(x, dict)}
    D = G.T @ arr["D"] @ G
    C = G.T @ arr["C"] @ G
    g = G.T @ arr["g"]
    tau = G.T @ arr["tau"]
    Minv = np.linalg.inv(D)
    Minv = (Minv + Minv.T) / 2
    tdata = tree.createData()
    aba = np.linalg.solve(D, tau - G.T @ pin.rnea(tree, tdata, q_tree, G @ v, 0 * (G @ v)))

    def coupled_derivatives(acceleration):
        d_q, d_v, _ = pin.computeRNEADerivatives(tree, tdata, q_tree, G @ v, G @ acceleration)
        return G.T @ d_q @ G, G.T @ d_v @ G

    dtau_dq, dtau_dv = coupled_derivatives(a)
    at_aba_dq, at_aba_dv = coupled_derivatives(aba)

    # Pinocchio's own values on the mimic model.
    data = model.createData()
    scale = 1.0 + np.abs(tau).max()
    worst.check("mimic model: crba = Gᵀ D_tree G", relative(symmetric_from_upper(pin.crba(model, data, q)) - D, D), 1e-12)
    worst.check("mimic model: rnea = Gᵀ τ_tree", float(np.abs(pin.rnea(model, data, q, v, a) - tau).max() / scale), 1e-9)
    worst.check("mimic model: g = Gᵀ g_tree", relative(pin.computeGeneralizedGravity(model, data, q) - g, g), 1e-9)
    worst.check("D a + C v + g = tau (coupled)", relative(D @ a + C @ v + g - tau, tau), 1e-9)
    worst.check("aba = a (coupled)", relative(aba - a, a), 1e-8)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    tree_frames_by_name = t["frames"]
    frames_out = {}
    for f in frames:
        name = model.frames[f].name
        values = tree_frames_by_name[name]
        J = np.array(values["J_lwa"]) @ G
        worst.check("mimic model: frame J = J_tree G", relative(pin.getFrameJacobian(model, data, f, LWA) - J, J), 1e-12)
        worst.check(
            "mimic model: frame pose",
            relative(data.oMf[f].translation - np.array(values["translation"]), np.array(values["translation"])),
            1e-12,
        )
        frames_out[name] = {
            "translation": values["translation"],
            "rotation": values["rotation"],
            "J_lwa": J.tolist(),
            "Jdot_lwa": (np.array(values["Jdot_lwa"]) @ G).tolist(),
            "J_local": (np.array(values["J_local"]) @ G).tolist(),
        }
    difference = np.concatenate([arr["difference"][:6], q_other[7:] - q[7:]])
    integrated = np.concatenate([arr["integrate"][:7], q[7:] + INTEGRATE_STEP * v[6:]])
    return {
        "q": q.tolist(),
        "v": v.tolist(),
        "a": a.tolist(),
        "vr": vr.tolist(),
        "ar": ar.tolist(),
        "D": D.tolist(),
        "C": C.tolist(),
        "g": g.tolist(),
        "tau": tau.tolist(),
        "tau_ref": (D @ ar + C @ vr + g).tolist(),
        "Y": (G.T @ arr["Y"]).tolist(),
        "aba": aba.tolist(),
        "Minv": Minv.tolist(),
        "dtau_dq": dtau_dq.tolist(),
        "dtau_dv": dtau_dv.tolist(),
        "dqdd_dq": (-Minv @ at_aba_dq).tolist(),
        "dqdd_dv": (-Minv @ at_aba_dv).tolist(),
        "com": t["com"],
        "Jcom": (arr["Jcom"] @ G).tolist(),
        "Ag": (arr["Ag"] @ G).tolist(),
        "hg": t["hg"],
        "dAg_v": t["dAg_v"],
        "kinetic_energy": t["kinetic_energy"],
        "potential_energy": t["potential_energy"],
        "frames": frames_out,
        "integrate": integrated.tolist(),
        "difference": difference.tolist(),
    }


def fixture(robot, worst):
    model, frames = build_model(robot, mimic=robot.mimic)
    pi = parameters(model)
    states = draw_states(model, robot.name, robot.states)
    evaluated = []
    tree, tree_frames = build_model(robot) if robot.mimic else (None, None)
    for i, (q, v, a, vr, ar) in enumerate(states):
        q_other = states[(i + 1) % len(states)][0]
        if tree is None:
            evaluated.append(evaluate(model, frames, pi, q, v, a, vr, ar, q_other, worst))
        else:
            evaluated.append(evaluate_mimic(model, tree, frames, tree_frames, q, v, a, vr, ar, q_other, worst))
    return {**describe_model(model, frames, robot, tree), "states": evaluated}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", help=f"any of {', '.join(ROBOTS)} (default: all)")
    parser.add_argument("--out", default=os.path.join(REPO, "codegen", "tests", "fixtures", "floating"))
    args = parser.parse_args()

    unknown = [r for r in args.robots if r not in ROBOTS]
    if unknown:
        parser.error(f"unknown robot(s) {', '.join(unknown)}; known: {', '.join(ROBOTS)}")
    for name in args.robots or list(ROBOTS):
        robot = ROBOTS[name]
        check_provenance(robot)
        worst = Worst()
        result = fixture(robot, worst)
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, name + ".json")
        with open(path, "w") as f:
            f.write(to_json(result) + "\n")
        print(f"{path}: nq {result['nq']}, nv {result['nv']}, {len(result['states'])} states")
        for check, value in worst.values.items():
            print(f"  {check:48} worst {value:.1e}")


if __name__ == "__main__":
    main()
