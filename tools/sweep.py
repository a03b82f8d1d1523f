#!/usr/bin/env python3
"""Sweep every fixed-base robot URDF of example-robot-data through dyngen and check the
generated code against Pinocchio.

A developer tool, not run by CI (it needs pip and minutes per large robot). For each URDF of
the pinned example-robot-data package (tools/requirements.txt):

1. It decides whether the robot is fixed-base (the rule is `CLASSIFICATION` below); floating-
   base robots (legged, humanoid, aerial, PR2) are listed as skipped with the reason.
2. It builds tests/sweep-harness/ with DYNGEN_SWEEP_DESCRIPTION=<the URDF>: the harness's
   build script loads the URDF with dyngen's loader exactly as a user's `build.rs` would (no
   options: dyngen picks the end-effector) and generates it into OUT_DIR; a URDF that does not
   load is recorded with dyngen's message, its warnings are recorded too.
3. For a robot that generated, Pinocchio builds the same URDF (`mimic=True` when the URDF has
   mimic joints, with the fields Pinocchio gets wrong or refuses on a mimic model taken from
   the same URDF without them through the coupling, as for the committed mimic fixtures;
   angles within 1e-9 rad of a quarter turn made exact, as dyngen's loader takes them), with
   dyngen's end-effector link as the frame, and writes reference values at seeded random
   states (tools/pinocchio_reference.py: the fields of the committed fixtures);
   the harness evaluates the compiled generated code at those states and reports the largest
   relative error per quantity. Everything must agree to 1e-9, as in the fixture tests.
4. It prints a Markdown table (the one in TESTING.md).

Set-up (once), from the repository root:

    python3 -m venv /tmp/fxenv
    /tmp/fxenv/bin/pip install -r tools/requirements.txt

Usage:

    /tmp/fxenv/bin/python tools/sweep.py                   # every fixed-base robot
    /tmp/fxenv/bin/python tools/sweep.py ur_description so100 # URDFs whose path contains a word
    /tmp/fxenv/bin/python tools/sweep.py --max-dof 24      # load all, generate up to 24 DOF
    /tmp/fxenv/bin/python tools/sweep.py --list            # the classification only
    /tmp/fxenv/bin/python tools/sweep.py --json sweep.json # also every number, as JSON
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import sysconfig
import tempfile
import time
import xml.etree.ElementTree as ET

import pinocchio as pin

from pinocchio_reference import (
    build_models,
    describe_model,
    draw_states,
    evaluate_states,
    exact_quarter_turns,
    to_json,
)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HARNESS = os.path.join(REPO, "tests", "sweep-harness")
ROBOTS = os.path.join(
    sysconfig.get_paths()["purelib"], "cmeel.prefix", "share", "example-robot-data", "robots"
)
TOLERANCE = 1e-9

# Fixed or floating base, per URDF (path below example-robot-data's robots/). The rule: where
# example-robot-data's own Python loaders (robots_loader.py upstream, now the separate
# example-robot-data-loaders package) load the URDF, their `free_flyer` attribute decides
# (False: fixed base). Where no loader names the file, the robot's kind decides: arms and hands
# are fixed-base, legged, humanoid and flying robots are not. A URDF missing from this table is
# reported as unclassified, so a new package version cannot slip robots past the sweep.
LOADER_FIXED = "loader: free_flyer = False"
LOADER_FLOATING = "loader: free_flyer = True"
CLASSIFICATION = {
    "a1_description/urdf/a1.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "alex_description/urdf/alex_nub_hands.urdf": (True, LOADER_FIXED),
    "alex_description/urdf/alex_psyonic_hands.urdf": (True, LOADER_FIXED),
    "alex_description/urdf/alex_sake_hands.urdf": (True, LOADER_FIXED),
    "alexander_description/urdf/alexander_v1.lowerBodyOnly.urdf": (False, "no loader; biped legs"),
    "allegro_hand_description/urdf/allegro_left_hand.urdf": (True, LOADER_FIXED),
    "allegro_hand_description/urdf/allegro_right_hand.urdf": (True, LOADER_FIXED),
    "anymal_b_simple_description/robots/anymal-kinova.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "anymal_b_simple_description/robots/anymal.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "anymal_c_simple_description/urdf/anymal.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "asr_twodof_description/urdf/TwoDofs.urdf": (True, LOADER_FIXED),
    "b1_description/urdf/b1-z1.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "b1_description/urdf/b1.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "baxter_description/urdf/baxter.urdf": (True, LOADER_FIXED),
    "bolt_description/robots/bolt.urdf": (False, LOADER_FLOATING + " (biped)"),
    "borinot_description/urdf/borinot_flying_arm_2.urdf": (False, LOADER_FLOATING + " (aerial)"),
    "centauro_description/urdf/centauro.urdf": (False, "no loader; legged (four wheeled legs)"),
    "double_pendulum_description/urdf/double_pendulum.urdf": (True, LOADER_FIXED),
    "double_pendulum_description/urdf/double_pendulum_continuous.urdf": (True, LOADER_FIXED),
    "double_pendulum_description/urdf/double_pendulum_simple.urdf": (True, LOADER_FIXED),
    "finger_edu_description/robots/finger_edu.urdf": (True, LOADER_FIXED),
    "g1_description/urdf/g1_29dof_rev_1_0.urdf": (False, "no loader; humanoid"),
    "g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf": (False, "no loader; humanoid"),
    "go1_description/urdf/go1.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "go2_description/urdf/go2.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "hector_description/robots/quadrotor_base.urdf": (False, LOADER_FLOATING + " (aerial)"),
    "hextilt_description/urdf/hextilt_flying_arm_5.urdf": (False, LOADER_FLOATING + " (aerial)"),
    "human_description/robots/human.urdf": (False, "no loader; human body"),
    "hyq_description/robots/hyq_no_sensors.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "icub_description/robots/icub.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "icub_description/robots/icub_reduced.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "iris_description/robots/iris.urdf": (False, "no loader; aerial (as iris_simple)"),
    "iris_description/robots/iris_simple.urdf": (False, LOADER_FLOATING + " (aerial)"),
    "kinova_description/robots/kinova.urdf": (True, LOADER_FIXED),
    "laikago_description/urdf/laikago.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "panda_description/urdf/panda.urdf": (True, LOADER_FIXED),
    "panda_description/urdf/panda_collision.urdf": (True, LOADER_FIXED),
    "pr2_description/urdf/pr2.urdf": (False, LOADER_FLOATING + " (mobile base)"),
    "quadruped_description/urdf/quadruped.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "romeo_description/urdf/romeo.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "romeo_description/urdf/romeo_laas_small.urdf": (False, "no loader; humanoid (as romeo)"),
    "romeo_description/urdf/romeo_small.urdf": (False, "no loader; humanoid (as romeo)"),
    "simple_humanoid_description/urdf/simple_humanoid.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "simple_humanoid_description/urdf/simple_humanoid_classical.urdf": (
        False,
        LOADER_FLOATING + " (humanoid)",
    ),
    "so_arm_description/urdf/so100.urdf": (True, "no loader; desk arm"),
    "so_arm_description/urdf/so101.urdf": (True, "no loader; desk arm"),
    "solo_description/robots/solo.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "solo_description/robots/solo12.urdf": (False, LOADER_FLOATING + " (quadruped)"),
    "talos_data/robots/talos_full_v2.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "talos_data/robots/talos_full_v2_box.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "talos_data/robots/talos_left_arm.urdf": (True, LOADER_FIXED),
    "talos_data/robots/talos_reduced.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "talos_data/robots/talos_reduced_box.urdf": (False, LOADER_FLOATING + " (humanoid)"),
    "talos_data/robots/talos_reduced_corrected.urdf": (False, "no loader; humanoid (as talos_reduced)"),
    "tiago_description/robots/tiago.urdf": (True, LOADER_FIXED + " (wheels are joints)"),
    "tiago_description/robots/tiago_dual.urdf": (True, LOADER_FIXED + " (wheels are joints)"),
    "tiago_description/robots/tiago_no_hand.urdf": (True, LOADER_FIXED + " (wheels are joints)"),
    "tiago_pro_description/robots/tiago_pro.urdf": (True, LOADER_FIXED + " (wheels are joints)"),
    "ur_description/urdf/ur10_joint_limited_robot.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur10_robot.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur3.urdf": (True, "no loader; UR arm"),
    "ur_description/urdf/ur3_gripper.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur3_joint_limited_robot.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur3_robot.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur5_gripper.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur5_joint_limited_robot.urdf": (True, LOADER_FIXED),
    "ur_description/urdf/ur5_robot.urdf": (True, LOADER_FIXED),
    "xarm_description/urdf/xarm7.urdf": (True, "no loader; arm (root link 'world')"),
    "z1_description/urdf/z1.urdf": (True, LOADER_FIXED),
}

# The quantities the harness reports, as table columns (pairs of derivatives in one column).
COLUMNS = [
    ("θ", ["theta"]),
    ("pose", ["ee pose"]),
    ("J", ["J"]),
    ("J̇", ["J̇"]),
    ("fused (pose, J, J̇)", ["kinematics (pose, J, J̇)"]),
    ("D", ["D"]),
    ("C", ["C"]),
    ("g", ["g"]),
    ("τ", ["τ"]),
    ("Slotine–Li", ["Slotine–Li τ"]),
    ("Y", ["Y"]),
    ("Y_b θ_b", ["Y_b θ_b"]),
    ("torque-form Y, Y_b θ_b", ["torque-form Y", "torque-form Y_b θ_b"]),
    ("FD", ["FD"]),
    ("D⁻¹", ["D⁻¹"]),
    ("∂τ/∂(q, q̇)", ["∂τ/∂q", "∂τ/∂q̇"]),
    ("∂q̈/∂(q, q̇)", ["∂q̈/∂q", "∂q̈/∂q̇"]),
]


def urdfs():
    """Every URDF of the package, as paths below its robots/ directory."""
    found = glob.glob(os.path.join(ROBOTS, "**", "*.urdf"), recursive=True)
    return sorted(os.path.relpath(p, ROBOTS) for p in found)


def has_mimic_joints(path):
    """A `<mimic>` on a moving joint (xacro also writes them on fixed joints, which mean nothing)."""
    root = ET.parse(path).getroot()
    return any(
        j.find("mimic") is not None and j.get("type") != "fixed" for j in root.iter("joint")
    )


# ---------------------------------------------------------------------------------------------
# dyngen: the harness


def build_harness(path, args):
    """Builds the harness for one URDF. Returns (ok, seconds, the compiler's last words)."""
    env = dict(os.environ, DYNGEN_SWEEP_DESCRIPTION=path, CARGO_TARGET_DIR=args.target_dir)
    env.pop("DYNGEN_SWEEP_MAX_DOF", None)
    if args.max_dof is not None:
        env["DYNGEN_SWEEP_MAX_DOF"] = str(args.max_dof)
    command = ["cargo", "build", "--quiet", "--manifest-path", os.path.join(HARNESS, "Cargo.toml")]
    if args.release:
        command.append("--release")
    start = time.monotonic()
    try:
        done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return False, time.monotonic() - start, f"build timed out after {args.timeout} s"
    errors = [line for line in done.stderr.splitlines() if line.startswith("error")]
    return done.returncode == 0, time.monotonic() - start, "; ".join(errors[:3]) or done.stderr[-500:]


def harness(args, *arguments):
    binary = os.path.join(args.target_dir, "release" if args.release else "debug", "dyngen-sweep-harness")
    done = subprocess.run([binary, *arguments], capture_output=True, text=True)
    if not done.stdout.strip():
        return {"error": f"harness exited with {done.returncode}: {done.stderr.strip()[-500:]}"}
    return json.loads(done.stdout)


# ---------------------------------------------------------------------------------------------
# Pinocchio: the reference values


def reference(path, end_effector, name, state_count):
    """Reference values for the URDF at `path`, end-effector frame `end_effector` (a link)."""
    with open(path) as f:
        urdf = exact_quarter_turns(f.read())
    model, tree = build_models(urdf, mimic=has_mimic_joints(path))
    if not model.existBodyName(end_effector):
        raise ValueError(f"Pinocchio has no body frame {end_effector!r}")
    frame = model.getFrameId(end_effector, pin.FrameType.BODY)
    states = draw_states(model, name, state_count)
    return {
        "robot": name,
        "urdf_path": "example-robot-data/robots/" + name,
        "pinocchio_version": pin.__version__,
        **describe_model(model, frame, tree),
        "states": evaluate_states(model, frame, states, tree),
    }


# ---------------------------------------------------------------------------------------------
# one robot


def sweep_one(name, args):
    path = os.path.join(ROBOTS, name)
    result = {"urdf": name, "mimic": has_mimic_joints(path)}
    ok, seconds, compiler = build_harness(path, args)
    result["build_seconds"] = round(seconds, 1)
    if not ok:
        result.update(status="build failed", message=compiler)
        return result
    outcome = harness(args, "outcome")
    shorten = lambda lines: [line.replace(path, name) for line in lines]  # noqa: E731
    result.update(
        dof=outcome.get("dof"),
        warnings=shorten(outcome.get("warnings", [])),
        notes=shorten(outcome.get("notes", [])),
        end_effector=outcome.get("end_effector"),
    )
    status = outcome.get("status", "harness error")
    if status != "generated":
        message = outcome.get("message") or outcome.get("error", "")
        result.update(status=status.replace("_", " "), message=message.replace(path, name))
        return result
    try:
        values = reference(path, outcome["end_effector"], name, args.states)
    except (ValueError, AssertionError, RuntimeError) as e:
        result.update(status="no reference", message=f"Pinocchio: {e}")
        return result
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        f.write(to_json(values))
    try:
        compared = harness(args, "compare", f.name)
    finally:
        os.unlink(f.name)
    if "error" in compared:
        result.update(status="not compared", message=compared["error"])
        return result
    errors = compared["max_relative_error"]
    result["errors"] = errors
    result["states"] = compared["states"]
    worst = max((e if e is not None else float("inf")) for e in errors.values())
    result["status"] = "matches" if worst <= TOLERANCE else "MISMATCH"
    return result


# ---------------------------------------------------------------------------------------------
# the table


def cell(errors, keys):
    values = [errors[k] for k in keys if k in errors]
    if not values:
        return "—"
    worst = max(float("inf") if v is None else v for v in values)
    return f"{worst:.0e}"


def escape(text):
    return text.replace("|", "\\|").replace("\n", " ")


def markdown(results, skipped):
    header = ["robot (package)", "URDF", "DOF", "result"] + [c for c, _ in COLUMNS]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in results:
        package, _, file = r["urdf"].partition("/")
        file = os.path.basename(file)
        row = [package.removesuffix("_description"), f"`{file}`", str(r.get("dof") or "—")]
        result = r["status"]
        if r.get("warnings"):
            result += f", {len(r['warnings'])} warning(s)"
        if "errors" in r:
            row += [result] + [cell(r["errors"], keys) for _, keys in COLUMNS]
        else:
            row += [result + ": " + escape(r.get("message", ""))] + [""] * len(COLUMNS)
        lines.append("| " + " | ".join(row) + " |")
    out = "\n".join(lines)
    warned = [r for r in results if r.get("warnings")]
    if warned:
        out += "\n\nWarnings (the model is generated all the same):\n\n"
        out += "\n".join(f"- `{w}`" for r in warned for w in r["warnings"])
    if skipped:
        out += "\n\nSkipped (not fixed-base):\n\n| URDF | reason |\n|---|---|\n"
        out += "\n".join(f"| `{name}` | {reason} |" for name, reason in skipped)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("filters", nargs="*", help="only URDFs whose path contains one of these")
    parser.add_argument("--list", action="store_true", help="print the classification and stop")
    parser.add_argument("--states", type=int, default=5, help="random states per robot (default 5)")
    parser.add_argument("--max-dof", type=int, help="load every robot, generate only up to this DOF")
    parser.add_argument("--release", action="store_true", help="build the harness optimised")
    parser.add_argument("--timeout", type=int, default=3600, help="seconds per harness build")
    parser.add_argument("--json", metavar="FILE", help="write every result as JSON")
    parser.add_argument(
        "--target-dir", default=os.path.join(REPO, "target", "sweep"), help="the harness's cargo target"
    )
    args = parser.parse_args()

    names = [n for n in urdfs() if not args.filters or any(f in n for f in args.filters)]
    unclassified = [n for n in names if n not in CLASSIFICATION]
    fixed = [n for n in names if CLASSIFICATION.get(n, (False,))[0]]
    skipped = [(n, CLASSIFICATION[n][1]) for n in names if n in CLASSIFICATION and not CLASSIFICATION[n][0]]
    skipped += [(n, "unclassified: add it to CLASSIFICATION in tools/sweep.py") for n in unclassified]
    if args.list:
        for n in names:
            fixed_base, reason = CLASSIFICATION.get(n, (None, "unclassified"))
            kind = {True: "fixed", False: "floating", None: "?"}[fixed_base]
            print(f"{kind:9} {n:70} {reason}")
        return

    start = time.monotonic()
    results = []
    for i, name in enumerate(fixed, 1):
        print(f"[{i}/{len(fixed)}] {name} …", file=sys.stderr, flush=True)
        r = sweep_one(name, args)
        print(f"    {r['status']} ({r['build_seconds']} s build) {r.get('message', '')}", file=sys.stderr)
        results.append(r)
    elapsed = time.monotonic() - start
    print(markdown(results, skipped))
    print(
        f"\n{len(results)} fixed-base URDFs, {len(skipped)} skipped; "
        f"{sum(r['status'] == 'matches' for r in results)} match Pinocchio to {TOLERANCE:.0e}; "
        f"{elapsed:.0f} s ({'release' if args.release else 'debug'} harness, "
        f"{args.states} states per robot, pin {pin.__version__})"
    )
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"results": results, "skipped": skipped, "seconds": elapsed}, f, indent=1)
    if any(r["status"] in ("MISMATCH", "build failed", "not compared") for r in results):
        sys.exit(1)


if __name__ == "__main__":
    main()
