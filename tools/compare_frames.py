#!/usr/bin/env python3
"""Side by side: dyngen's generated named-frame functions (the group `frames`) and numeric
Pinocchio 4.1's equivalent calls, on the Panda and the UR5, interleaved, pinned to one core;
prints a Markdown table.

For developers (not CI). The dyngen side is `generated/benches/frames.rs` (criterion); the
Pinocchio side is the C++ program of `tools/anchors/frames/` (build it first with its
`build.sh`, see its README.md):

    tools/anchors/frames/build.sh
    tools/compare_frames.py                      # 3 rounds, the default build of dyngen
    tools/compare_frames.py --rounds 5 --builds default native

Each round runs `cargo bench -p dyngen-generated --bench frames -- --measurement-time 1`
(criterion's medians read back from its JSON estimates) and the anchor, one after the other,
both pinned with `taskset -c 1`. Both time each call over the same 256 random states, the
joint sines and cosines included on dyngen's side. Times are medians over the rounds; a ratio
is the median of the per-round ratios. `--builds native` also (or only) times dyngen built with
`RUSTFLAGS="-C target-cpu=native"` (in target/bench-native), as the anchor is built with
`-march=native`; `default` is the plain build (target/), which picks AVX2/FMA copies at run
time. The last column is the operation count of the generated function the call runs (its
`Operations:` doc comment in generated/src/<robot>.rs).

Run it on an otherwise idle machine: the two vCPUs behave like SMT siblings, so a compile on
the other one slows a benchmark 1.3-2x (BENCHMARKS.md). `--record benchmarks/results.csv
--machine KIND` appends the run's medians to the results file BENCHMARKS.md's tables are
rendered from (`cargo xtask bench-render`). Standard library only; reuses
tools/compare_anchors.py's helpers.
"""

import os
import re
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_anchors import (ONE_ANCHOR_FLOOR, ROOT, anchor_rows, cargo_env, fmt,  # noqa: E402
                             fresh_medians, med, number, one_anchor_arguments, one_anchor_head,
                             record_rows, run, warn_missing)

# robot -> (tool frame, mid-chain frame, end-effector), as generated/benches/frames.rs.
ROBOTS = {
    "panda": ("panda_link8", "panda_link4", "panda_hand_tcp"),
    "ur5": ("ee_link", "forearm_link", "tool0"),
    "ur5_aligned": ("ee_link", "forearm_link", "tool0"),
}
# The UR5 with LOCAL and WORLD converted at run time (`frame_references: aligned`): timed
# against the anchor's UR5, its module generated/src/ur5_aligned_frames.rs.
ANCHOR_ROBOT = {"ur5_aligned": "ur5"}
MODULE = {"ur5_aligned": "ur5_aligned_frames"}
# The references as the group names spell them (`lwa`: LOCAL_WORLD_ALIGNED; criterion cuts
# directory names at 64 characters, too short for the full keyword).
REFERENCES = ("local", "world", "lwa")
# Timed per frame, in table order.
FRAME_FUNCTIONS = (["frame_pose"]
                   + [f"frame_jacobian_{r}" for r in REFERENCES]
                   + [f"frame_jacobian_time_variation_{r}" for r in REFERENCES]
                   + ["frame_velocity_local", "frame_classical_acceleration_local", "frame_kinematics"])


def functions(robot):
    """[(function, frame)] of one robot, in table order: the criterion group is
    `<robot>/<function>/<frame>`, the anchor's row `<function>/<frame>`."""
    tool, mid, end_effector = ROBOTS[robot]
    rows = [(fn, frame) for frame in (tool, mid) for fn in FRAME_FUNCTIONS]
    return rows + [("inverse_dynamics_with_wrenches", tool), ("jacobian", end_effector)]


def dyngen_build(env):
    """Builds the bench before the rounds, so that no round times a compile."""
    cmd = ["cargo", "bench", "-p", "dyngen-generated", "--bench", "frames", "--no-run", "-j", "1"]
    subprocess.run(cmd, cwd=ROOT, env=env, check=True)


def dyngen_round(env, core, target_dir, robots, seconds):
    """{(robot, "function/frame"): median_ns} of one criterion run of the frames bench; only
    estimates written by this run are read."""
    start = time.time()
    timing = ["--warm-up-time", f"{seconds / 3:g}", "--measurement-time", f"{seconds:g}"]
    pattern = "^(" + "|".join(re.escape(r) for r in robots) + ")/.*/generated$"
    run(["taskset", "-c", str(core), "cargo", "bench", "-q", "-p", "dyngen-generated",
         "--bench", "frames", "--", pattern, *timing], cwd=ROOT, env=env)
    wanted = {(r, f"{fn}/{frame}") for r in robots for fn, frame in functions(r)}
    return {key: ns for key, ns in fresh_medians(target_dir, robots, start).items() if key in wanted}


def operation_counts(robot):
    """{(function, frame): "mul/add/neg"} of the generated functions the bench's calls run,
    from the `Operations:` doc comments of generated/src/<robot>.rs and the match arms of its
    `FrameKinematics` impl."""
    try:
        source = (ROOT / "generated" / "src" / f"{MODULE.get(robot, robot)}.rs").read_text()
    except OSError:
        return {}
    ops = {}
    for m in re.finditer(r"///Operations: (\d+) mul, (\d+) add/sub, (\d+) neg.*\n(?:\s*#\[.*\]\n)*\s*fn (\w+)\(",
                         source):
        ops[m.group(4)] = tuple(int(x) for x in m.group(1, 2, 3))
    impl = source.find("impl FrameKinematics<")
    if impl < 0:
        return {}
    body = source[impl:]
    camel = lambda name: "".join(p[:1].upper() + p[1:] for p in name.split("_"))
    variant = {"local": "Local", "world": "World", "lwa": "LocalWorldAligned"}

    def callee(method, frame, reference=None):
        start = body.find(f"fn {method}(")
        end = body.find("\n    fn ", start + 1)
        text = body[start:end if end > 0 else None]
        arm = (rf"\(Frame::{camel(frame)}, ReferenceFrame::{variant[reference]}\)" if reference
               else rf"Frame::{camel(frame)}")
        m = re.search(arm + r"\s*=>\s*\{?\s*(?:Self::)?(\w+)\(", text)
        return m.group(1) if m else None

    counts = {}
    tool, mid, end_effector = ROBOTS[robot]
    for frame in (tool, mid):
        for fn in FRAME_FUNCTIONS:
            reference = next((r for r in REFERENCES if fn.endswith("_" + r)), None)
            method = fn[: -len(reference) - 1] if reference else fn
            counts[(fn, frame)] = ops.get(callee(method, frame, reference))
    # τ − Jᵀw: inverse dynamics and the tool frame's LOCAL Jacobian (plus 6N for Jᵀw, uncounted).
    rnea, jac = ops.get("inverse_dynamics"), ops.get(callee("frame_jacobian", tool, "local"))
    counts[("inverse_dynamics_with_wrenches", tool)] = (
        tuple(a + b for a, b in zip(rnea, jac)) if rnea and jac else None)
    counts[("jacobian", end_effector)] = ops.get("jacobian")
    return counts


def main():
    args = one_anchor_arguments(__doc__.split("\n\n")[0], ROBOTS, ("default", "native"), "default",
                                "frames/build/bench_frames")
    robots, builds = args.robots, args.builds

    dirs = {"default": ROOT / "target", "native": ROOT / "target" / "bench-native"}
    envs = {b: cargo_env(dirs[b], b == "native") for b in builds}
    for b in builds:
        print(f"building the frames bench ({b})", file=sys.stderr)
        dyngen_build(envs[b])

    anchor_env = dict(os.environ, BENCH_SECONDS=f"{args.measurement_time:g}")
    anchored = list(dict.fromkeys(ANCHOR_ROBOT.get(r, r) for r in robots))
    pin_cmd = ["taskset", "-c", str(args.core), str(args.anchor), str(args.anchor.parent / "models"), *anchored]

    def anchor_of(text):
        rows = anchor_rows(text, anchored)
        return {(robot, fn): ns for robot in robots for (r, fn), ns in rows.items()
                if r == ANCHOR_ROBOT.get(robot, robot)}
    load_start = os.getloadavg()
    rounds = []
    for r in range(args.rounds):
        print(f"round {r + 1}/{args.rounds}", file=sys.stderr)
        pin = anchor_of(run(pin_cmd, env=anchor_env))
        ours = {b: dyngen_round(envs[b], args.core, dirs[b], robots, args.measurement_time) for b in builds}
        rounds.append((pin, ours))
        if r == 0:
            warn_missing([(robot, f"{fn}/{frame}") for robot in robots for fn, frame in functions(robot)],
                         pin, ours)

    print(one_anchor_head(load_start, args, ["robot", "function", "frame", "Pinocchio"],
                          "generated ops (mul/add/neg)"))
    missed = []
    for robot in robots:
        counts = operation_counts(robot)
        for fn, frame in functions(robot):
            key = (robot, f"{fn}/{frame}")
            pin = [p.get(key) for p, _ in rounds]
            row = f"| {robot} | {fn} | {frame} | {fmt(med(pin))} |"
            for b in builds:
                ours = [o[b].get(key) for _, o in rounds]
                ratio = med([p / d for p, d in zip(pin, ours) if p and d])
                low = ratio is not None and ratio < ONE_ANCHOR_FLOOR and fn != "jacobian"
                if low:
                    missed.append(f"{robot} {fn}/{frame} ({b}): {ratio:.2f}×")
                row += f" {fmt(med(ours))} | {fmt(ratio, 2, '×')}{' **missed**' if low else ''} |"
            ops = counts.get((fn, frame))
            print(row + (f" {'/'.join(map(str, ops))} |" if ops else " – |"))
    if missed:
        print(f"\nBelow {ONE_ANCHOR_FLOOR:g}×: " + "; ".join(missed))
    if args.record:
        rows = []
        for robot in robots:
            for fn, frame in functions(robot):
                key = (robot, f"{fn}/{frame}")
                pin = med([p.get(key) for p, _ in rounds])
                for b in builds:
                    ns = med([o[b].get(key) for _, o in rounds])
                    if ns is not None:
                        rows.append({"build": b, "robot": robot, "function": fn, "frame": frame,
                                     "form": "value", "dyngen_ns": number(ns), "pinocchio_ns": number(pin)})
        record_rows(args.record, args.machine, args.date, rows)


if __name__ == "__main__":
    main()
