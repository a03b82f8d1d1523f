#!/usr/bin/env python3
"""Regenerate the Pinocchio reference fixtures of named frames and external wrenches,
codegen/tests/fixtures/frames/.

A developer tool, not run by CI. For the Panda and the UR5 it builds exactly the Pinocchio
model tools/fixtures.py builds (same committed URDFs, fixed joints merged, panda fingers locked
at 0: `build_model` and `ROBOTS` are imported from it), takes the first states of the existing
fixtures codegen/tests/fixtures/<robot>.json, and writes, for every BODY frame of the model
(one per URDF link) and each state, the frame's pose, Jacobian, Jacobian time variation,
velocity and classical acceleration in Pinocchio's three reference frames, and, per state,
inverse and forward dynamics under seeded random external wrenches applied at those frames.
Field meanings and conventions: codegen/tests/fixtures/README.md ("Frames and external
wrenches"). Before writing, it checks every value against an independent identity (J v,
finite differences of J, J a + J̇ v, Jᵀ w, rnea ∘ aba) and stops at the first failure.

Set-up (once):

    python3 -m venv /tmp/fxenv
    /tmp/fxenv/bin/pip install -r tools/requirements.txt

Usage (from the repository root):

    /tmp/fxenv/bin/python tools/frame_fixtures.py                  # panda, ur5 -> codegen/tests/fixtures/frames/
    /tmp/fxenv/bin/python tools/frame_fixtures.py ur5 --out /tmp/fx  # one robot, elsewhere
    /tmp/fxenv/bin/python tools/frame_fixtures.py --states-from /tmp/fx0
        # take the states from DIR/<robot>.json instead of codegen/tests/fixtures/

Run twice, it writes byte-identical files.
"""

import argparse
import json
import os
import sys

import numpy as np
import pinocchio as pin

from fixtures import REPO, ROBOTS, build_model
from pinocchio_reference import seed_of, to_json

DEFAULT_ROBOTS = ("panda", "ur5")
STATES = 8  # the first states of the existing fixture
WRENCHES = 3  # external wrenches per state

# Pinocchio's reference frames, by the names the file uses. A wrench's `reference` cycles
# through them in this order.
REFERENCES = {
    "local": pin.ReferenceFrame.LOCAL,
    "world": pin.ReferenceFrame.WORLD,
    "local_world_aligned": pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
}

FORCE_RANGE = 20.0  # N, each force component uniform in [-FORCE_RANGE, FORCE_RANGE]
TORQUE_RANGE = 3.0  # N·m, each torque component alike
TAU_PERTURBATION = 5.0  # N·m (or N), tau_aba = rnea(q, v, a) + U(-5, 5) per joint
FD_STEP = 1e-6  # step of the central difference of J along q(t) = q ⊕ v t


# ---------------------------------------------------------------------------------------------
# model


def body_frames(model):
    """The BODY frames (one per URDF link, merged links included), in Pinocchio's order.
    "universe" and the JOINT/FIXED_JOINT frames are left out: each coincides with its child
    link's frame."""
    return [i for i, f in enumerate(model.frames) if f.type == pin.FrameType.BODY]


def describe_frame(model, fid):
    frame = model.frames[fid]
    return {
        "name": frame.name,
        "parent_joint": model.names[frame.parentJoint],
        "placement": {
            "translation": frame.placement.translation.tolist(),
            "rotation": frame.placement.rotation.tolist(),
        },
    }


# ---------------------------------------------------------------------------------------------
# kinematics of the frames


def frame_jacobians(model, data, fid):
    """J of frame `fid` in the three reference frames, from data.J and data.oMi."""
    return {k: pin.getFrameJacobian(model, data, fid, rf).copy() for k, rf in REFERENCES.items()}


def jacobians_at(model, q, frames):
    data = model.createData()
    pin.computeJointJacobians(model, data, q)
    return {fid: frame_jacobians(model, data, fid) for fid in frames}


def close(actual, expected, tolerance, what):
    """max |actual − expected| ≤ tolerance · (1 + max |expected|)."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    error = float(np.abs(actual - expected).max())
    scale = 1.0 + float(np.abs(expected).max())
    assert error <= tolerance * scale, f"{what}: {error:.3e} > {tolerance:.0e} · {scale:.3e}"
    return error / scale


class Worst:
    """The largest relative error of each check, reported at the end."""

    def __init__(self):
        self.errors = {}

    def check(self, name, actual, expected, tolerance, what):
        e = close(actual, expected, tolerance, what)
        self.errors[name] = max(self.errors.get(name, 0.0), e)


def evaluate_frames(model, q, v, a, frames, worst, label):
    data = model.createData()
    pin.forwardKinematics(model, data, q, v, a)
    pin.computeJointJacobians(model, data, q)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    pin.updateFramePlacements(model, data)

    # J̇ independently: central differences of J along q(t) = q ⊕ v t.
    plus = jacobians_at(model, pin.integrate(model, q, v * FD_STEP), frames)
    minus = jacobians_at(model, pin.integrate(model, q, -v * FD_STEP), frames)

    result = {}
    for fid in frames:
        name = model.frames[fid].name
        oMf = data.oMf[fid]
        J = frame_jacobians(model, data, fid)
        dJ = {k: pin.getFrameJacobianTimeVariation(model, data, fid, rf).copy() for k, rf in REFERENCES.items()}
        velocity = {k: pin.getFrameVelocity(model, data, fid, rf).vector.copy() for k, rf in REFERENCES.items()}
        classical = {
            k: pin.getFrameClassicalAcceleration(model, data, fid, rf).vector.copy() for k, rf in REFERENCES.items()
        }
        where = f"{label}, frame {name}"
        for k in REFERENCES:
            worst.check("velocity = J v", velocity[k], J[k] @ v, 1e-9, f"{where}: velocity ({k}) = J v")
            fd = (plus[fid][k] - minus[fid][k]) / (2 * FD_STEP)
            worst.check("dJ = d/dt J (central differences)", dJ[k], fd, 1e-6, f"{where}: dJ ({k}) = d/dt J")
        # Classical acceleration in LOCAL_WORLD_ALIGNED: the frame origin's p̈ and ω̇, world
        # axes, both the time derivative of J_lwa v.
        lwa = J["local_world_aligned"] @ a + dJ["local_world_aligned"] @ v
        worst.check(
            "classical_acceleration (lwa, linear) = (J a + dJ v) linear",
            classical["local_world_aligned"][:3],
            lwa[:3],
            1e-9,
            f"{where}: classical acceleration, linear",
        )
        worst.check(
            "classical_acceleration (lwa, angular) = (J a + dJ v) angular",
            classical["local_world_aligned"][3:],
            lwa[3:],
            1e-9,
            f"{where}: classical acceleration, angular",
        )
        # LOCAL: the same vectors in the frame's axes.
        R, p = oMf.rotation, oMf.translation
        worst.check(
            "classical_acceleration (local) = R^T classical_acceleration (lwa)",
            classical["local"],
            np.concatenate([R.T @ lwa[:3], R.T @ lwa[3:]]),
            1e-9,
            f"{where}: classical acceleration, local",
        )
        # WORLD: the acceleration of the body's material point now at the world origin,
        # p̈ + p × ω̇ + ω × (p × ω), not that of the frame origin.
        w = velocity["local_world_aligned"][3:]
        worst.check(
            "classical_acceleration (world) = acceleration of the body point at the world origin",
            classical["world"],
            np.concatenate([lwa[:3] + np.cross(p, lwa[3:]) + np.cross(w, np.cross(p, w)), lwa[3:]]),
            1e-9,
            f"{where}: classical acceleration, world",
        )
        worst.check(
            "J (local) = Ad(oMf)^-1 J (world)", J["local"], oMf.inverse().toActionMatrix() @ J["world"], 1e-12,
            f"{where}: J local from J world",
        )
        worst.check(
            "J (lwa) = [R 0; 0 R] J (local)",
            J["local_world_aligned"],
            np.vstack([R @ J["local"][:3], R @ J["local"][3:]]),
            1e-12,
            f"{where}: J lwa from J local",
        )
        result[name] = {
            "translation": oMf.translation.tolist(),
            "rotation": oMf.rotation.tolist(),
            "J": {k: m.tolist() for k, m in J.items()},
            "dJ": {k: m.tolist() for k, m in dJ.items()},
            "velocity": {k: m.tolist() for k, m in velocity.items()},
            "classical_acceleration": {k: m.tolist() for k, m in classical.items()},
        }
    return data, result


# ---------------------------------------------------------------------------------------------
# external wrenches


def joint_force(model, data, fid, reference, wrench):
    """The wrench [f; τ] applied at frame `fid` in `reference`, as Pinocchio's fext entry of the
    frame's parent joint: a force acting on the body, about the joint origin, joint axes."""
    frame = model.frames[fid]
    f = pin.Force(wrench[:3], wrench[3:])
    if reference == "local_world_aligned":
        R = data.oMf[fid].rotation
        f = pin.Force(R.T @ f.linear, R.T @ f.angular)
        reference = "local"
    if reference == "local":
        return frame.placement.act(f)
    if reference == "world":
        return data.oMi[frame.parentJoint].actInv(f)
    raise ValueError(reference)


def evaluate_wrenches(model, data, q, v, a, frames, rng, worst, label):
    """WRENCHES wrenches at random moving frames, reference cycling through REFERENCES, and the
    dynamics they cause. `data` holds the placements and Jacobians at q."""
    moving = [fid for fid in frames if model.frames[fid].parentJoint != 0]
    references = list(REFERENCES)
    wrenches = []
    fext = pin.StdVec_Force()
    for _ in range(model.njoints):
        fext.append(pin.Force.Zero())
    for k in range(WRENCHES):
        fid = moving[int(rng.integers(len(moving)))]
        force = rng.uniform(-FORCE_RANGE, FORCE_RANGE, 3)
        torque = rng.uniform(-TORQUE_RANGE, TORQUE_RANGE, 3)
        wrench = np.concatenate([force, torque])
        reference = references[k % len(references)]
        joint = model.frames[fid].parentJoint
        fext[joint] = fext[joint] + joint_force(model, data, fid, reference, wrench)
        wrenches.append({"frame": model.frames[fid].name, "reference": reference, "wrench": wrench})
    perturbation = rng.uniform(-TAU_PERTURBATION, TAU_PERTURBATION, model.nv)

    scratch = model.createData()
    tau = pin.rnea(model, scratch, q, v, a).copy()
    tau_fext = pin.rnea(model, scratch, q, v, a, fext).copy()
    tau_aba = tau + perturbation
    qdd_fext = pin.aba(model, scratch, q, v, tau_aba, fext).copy()

    # tau_fext = rnea(q, v, a) − Σ Jᵀ w, J the frame's Jacobian in the wrench's reference.
    expected = tau.copy()
    for w in wrenches:
        fid = model.getFrameId(w["frame"], pin.FrameType.BODY)
        J = pin.getFrameJacobian(model, data, fid, REFERENCES[w["reference"]])
        expected -= J.T @ w["wrench"]
    worst.check("tau_fext = rnea(q,v,a) - sum J^T w", tau_fext, expected, 1e-9, f"{label}: tau_fext")
    # aba with fext inverts rnea with fext.
    again = pin.rnea(model, scratch, q, v, qdd_fext, fext)
    worst.check("rnea(q,v,qdd_fext,fext) = tau_aba", again, tau_aba, 1e-9, f"{label}: aba with fext")

    for w in wrenches:
        w["wrench"] = w["wrench"].tolist()
    return {
        "wrenches": wrenches,
        "tau_fext": tau_fext.tolist(),
        "tau_aba": tau_aba.tolist(),
        "qdd_fext": qdd_fext.tolist(),
    }


# ---------------------------------------------------------------------------------------------
# file


def fixture(robot, given_states, worst):
    if robot.mimic:
        sys.exit(f"{robot.name}: mimic models are not supported")
    model, _, _ = build_model(robot)
    frames = body_frames(model)
    states = []
    for k, s in enumerate(given_states[:STATES]):
        q = np.array(s["q"], dtype=float)
        q_pin = pin.integrate(model, pin.neutral(model), q)
        if "q_pinocchio" in s:
            assert np.array_equal(q_pin, np.array(s["q_pinocchio"])), f"{robot.name}: q_pinocchio of state {k}"
        v = np.array(s["v"], dtype=float)
        a = np.array(s["a"], dtype=float)
        label = f"{robot.name}, state {k}"
        data, frame_values = evaluate_frames(model, q_pin, v, a, frames, worst, label)
        # One generator per robot and state: (CRC-32 of the robot's name, state index).
        rng = np.random.default_rng([seed_of(robot.name), k])
        state = {"q": q.tolist()}
        if model.nq != model.nv:
            state["q_pinocchio"] = q_pin.tolist()
        state.update({"v": v.tolist(), "a": a.tolist(), "frames": frame_values})
        state.update(evaluate_wrenches(model, data, q_pin, v, a, frames, rng, worst, label))
        states.append(state)
    return {
        "robot": robot.name,
        "pinocchio_version": pin.__version__,
        "nv": model.nv,
        "joint_names": [model.names[j] for j in range(1, model.njoints)],
        "frames": [describe_frame(model, fid) for fid in frames],
        "states": states,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", help=f"any of {', '.join(DEFAULT_ROBOTS)} (default: both)")
    parser.add_argument("--out", default=os.path.join(REPO, "codegen", "tests", "fixtures", "frames"))
    parser.add_argument(
        "--states-from",
        metavar="DIR",
        default=os.path.join(REPO, "codegen", "tests", "fixtures"),
        help="take q, v, a from DIR/<robot>.json (default: codegen/tests/fixtures)",
    )
    args = parser.parse_args()

    unknown = [r for r in args.robots if r not in DEFAULT_ROBOTS]
    if unknown:
        parser.error(f"unknown robot(s) {', '.join(unknown)}; known: {', '.join(DEFAULT_ROBOTS)}")
    worst = Worst()
    for name in args.robots or DEFAULT_ROBOTS:
        with open(os.path.join(args.states_from, name + ".json")) as f:
            given = json.load(f)["states"]
        result = fixture(ROBOTS[name], given, worst)
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, name + ".json")
        with open(path, "w") as f:
            f.write(to_json(result) + "\n")
        print(f"{path}: {result['nv']} DOF, {len(result['frames'])} frames, {len(result['states'])} states")
    print("largest relative error of each check (error / (1 + max |expected|)):")
    for check, error in worst.errors.items():
        print(f"  {error:.1e}  {check}")


if __name__ == "__main__":
    main()
