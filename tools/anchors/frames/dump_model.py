#!/usr/bin/env python3
"""Writes the Pinocchio models of the frames anchor as text, build/models/<robot>.txt, which
bench_frames reads back into a header-only Pinocchio built with -march=native.

Why not parse the URDF in bench_frames itself: the wheel's libpinocchio_parsers is compiled
for the default x86-64, and Eigen lays fixed-size members out differently under
-march=native (AVX-512: 64-byte alignment), so a Model built by the library and used by code
compiled with -march=native crashes. The text carries every number as Python's repr (exact).

The models are those of tools/fixtures.py (`build_model`): the committed URDF, links joined
by fixed joints merged, the Panda's fingers locked at 0 with buildReducedModel.

    /tmp/pinenv/bin/python dump_model.py REPO OUT_DIR [ROBOT...]   (run by build.sh)
"""

import os
import sys

import pinocchio as pin

# robot -> (committed URDF, joints locked at 0); the robots of bench_frames.cpp.
ROBOTS = {
    "panda": ("robots/urdf/panda.urdf", ["panda_finger_joint1", "panda_finger_joint2"]),
    "ur5": ("robots/urdf/ur5_robot.urdf", []),
}
# The joint types bench_frames rebuilds.
JOINT_TYPES = {"JointModelRX", "JointModelRY", "JointModelRZ",
               "JointModelPX", "JointModelPY", "JointModelPZ"}


def model_of(repo, robot):
    urdf, locked = ROBOTS[robot]
    model = pin.buildModelFromUrdf(os.path.join(repo, urdf))
    if locked:
        ids = [model.getJointId(j) for j in locked]
        if any(i >= model.njoints for i in ids):
            sys.exit(f"{robot}: a locked joint is missing: {locked}")
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
    return model


def numbers(xs):
    return " ".join(repr(float(x)) for x in xs)


def se3(m):
    return numbers(m.rotation.reshape(-1)) + " " + numbers(m.translation)


def dump(model, name):
    lines = [f"model {name} {model.njoints - 1} {len(model.frames) - 1}",
             "gravity " + numbers(model.gravity.linear)]
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.shortname() not in JOINT_TYPES:
            sys.exit(f"{name}: joint {model.names[j]} is a {joint.shortname()}, which bench_frames "
                     "does not rebuild")
        y = model.inertias[j]
        lines.append(f"joint {model.names[j]} {joint.shortname()} {model.parents[j]} "
                     f"{se3(model.jointPlacements[j])} {y.mass!r} {numbers(y.lever)} "
                     f"{numbers(y.inertia.reshape(-1))}")
    for f in model.frames[1:]:
        lines.append(f"frame {f.name} {int(f.type)} {f.parentJoint} {f.parentFrame} {se3(f.placement)}")
    return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    repo, out = sys.argv[1], sys.argv[2]
    robots = sys.argv[3:] or list(ROBOTS)
    os.makedirs(out, exist_ok=True)
    for robot in robots:
        model = model_of(repo, robot)
        with open(os.path.join(out, f"{robot}.txt"), "w") as f:
            f.write(dump(model, robot))
        print(f"{robot}: nq {model.nq}, {model.njoints - 1} joints, {len(model.frames) - 1} frames "
              f"-> {out}/{robot}.txt")


if __name__ == "__main__":
    main()
