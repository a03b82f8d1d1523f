#!/usr/bin/env python3
"""Writes the Pinocchio models of the frames anchor as text, build/models/<robot>.txt, which
bench_frames reads back into a header-only Pinocchio built with -march=native (why text:
../common/model_text.py).

The models are those of tools/fixtures.py (`build_model`): the committed URDF, links joined
by fixed joints merged, the Panda's fingers locked at 0 with buildReducedModel.

    /tmp/pinenv/bin/python dump_model.py REPO OUT_DIR [ROBOT...]   (run by build.sh)
"""

import os
import sys

import pinocchio as pin

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from model_text import dump  # noqa: E402

# robot -> (committed URDF, joints locked at 0); the robots of bench_frames.cpp.
ROBOTS = {
    "panda": ("robots/urdf/panda.urdf", ["panda_finger_joint1", "panda_finger_joint2"]),
    "ur5": ("robots/urdf/ur5_robot.urdf", []),
}


def model_of(repo, robot):
    urdf, locked = ROBOTS[robot]
    model = pin.buildModelFromUrdf(os.path.join(repo, urdf))
    if locked:
        ids = [model.getJointId(j) for j in locked]
        if any(i >= model.njoints for i in ids):
            sys.exit(f"{robot}: a locked joint is missing: {locked}")
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
    return model


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
