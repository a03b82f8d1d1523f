"""Writes a Pinocchio model as text, which the anchors under tools/anchors/ read back
(common/model_text.hpp) into a header-only Pinocchio built with -march=native.

Why not parse the URDF in the anchors themselves: the wheel's libpinocchio_parsers is compiled
for the default x86-64, and Eigen lays fixed-size members out differently under -march=native
(AVX-512: 64-byte alignment), so a Model built by the library and used by code compiled with
-march=native crashes. The text carries every number as Python's repr (exact).
"""

import sys

# The joint types model_text.hpp rebuilds.
JOINT_TYPES = {"JointModelRX", "JointModelRY", "JointModelRZ",
               "JointModelPX", "JointModelPY", "JointModelPZ", "JointModelFreeFlyer"}


def numbers(xs):
    return " ".join(repr(float(x)) for x in xs)


def se3(m):
    return numbers(m.rotation.reshape(-1)) + " " + numbers(m.translation)


def dump(model, name):
    """The model as text: a header, the gravity, every joint (type, parent, placement, inertia)
    and every frame."""
    lines = [f"model {name} {model.njoints - 1} {len(model.frames) - 1}",
             "gravity " + numbers(model.gravity.linear)]
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.shortname() not in JOINT_TYPES:
            sys.exit(f"{name}: joint {model.names[j]} is a {joint.shortname()}, which the anchors "
                     "do not rebuild")
        y = model.inertias[j]
        lines.append(f"joint {model.names[j]} {joint.shortname()} {model.parents[j]} "
                     f"{se3(model.jointPlacements[j])} {y.mass!r} {numbers(y.lever)} "
                     f"{numbers(y.inertia.reshape(-1))}")
    for f in model.frames[1:]:
        lines.append(f"frame {f.name} {int(f.type)} {f.parentJoint} {f.parentFrame} {se3(f.placement)}")
    return "\n".join(lines) + "\n"
