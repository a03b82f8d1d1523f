#!/usr/bin/env python3
"""Side by side: dyngen's constrained dynamics and numeric Pinocchio 4.1's, on Solo-12 (four
point feet) and the Unitree G1 (two feet held as frames), interleaved, pinned to one core;
prints a Markdown table.

For developers (not CI). The dyngen side is `generated/benches/common/constrained.rs`, timed
for Solo-12 by `cargo bench -p dyngen-generated --bench contacts` and for the G1 by the crate
`tools/anchors/contacts/dyngen/` (the G1 is not a committed robot: its build script generates
it); the Pinocchio side is the C++ program of `tools/anchors/contacts/` (build it first with
its `build.sh`, see its README.md):

    tools/anchors/contacts/build.sh
    tools/compare_contacts.py                          # 3 rounds, dyngen built native
    tools/compare_contacts.py --rounds 5 --builds native default --robots solo12

Each round runs the anchor, then each robot's dyngen bench (criterion's medians read back from
its JSON estimates), one after the other, all pinned with `taskset -c 1`. Both sides time each
call over the same 256 random states and anchors (the SplitMix64 stream of seed 18), with the
same settings; both print, per function, the sum over the states of the result's norm, and the
table's last column says where the two sums differ (they should agree to rounding: the same
states, anchors and quantity). Times are medians over the rounds; a ratio is the median of the
per-round ratios. Below the table, where each solve's time goes: the generated pieces it calls
and what the runtime adds to them.

Run it on an otherwise idle machine: the two vCPUs behave like SMT siblings, so a compile on
the other one slows a benchmark 1.3-2x (BENCHMARKS.md). `--record benchmarks/results.csv
--machine KIND` appends the run's medians to the results file BENCHMARKS.md's tables are
rendered from (`cargo xtask bench-render`: the table of a `<!-- rendered: KIND / contacts -->`
marker). Standard library only; reuses tools/compare_anchors.py's helpers.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_anchors import (ONE_ANCHOR_FLOOR, ROOT, anchor_rows,  # noqa: E402
                             criterion_run, fmt, fresh_medians, med, number, one_anchor_head,
                             record_rows, solo12_and_g1_setup, warn_missing)

ANCHOR = ROOT / "tools" / "anchors" / "contacts"
G1_CRATE = ANCHOR / "dyngen"
# The table's functions, in its order: dyngen's criterion group `<robot>/<function>` and the
# anchor's row of the same name (the anchor also times a slower second way of Λ and of J,
# `operational_space_inertia_cholesky` and `contact_jacobian_constraints`:
# tools/anchors/contacts/README.md).
FUNCTIONS = [
    "constrained_forward_dynamics",
    "constrained_forward_dynamics_baumgarte",
    "constrained_forward_dynamics_proximal",
    "impulse_dynamics",
    "operational_space_inertia",
    "contact_jacobian",
    "contact_drift",
    "contact_response",
    "constrained_forward_dynamics_derivatives",
]
# The generated call each solve makes (one generated function, which shares the kinematics, the
# factored mass matrix and the factored Delassus matrix within it): the breakdown below the
# table, not recorded.
PIECES = ("contact_solve", "contact_proximal_solve", "contact_impulse", "contact_inertia")
SOLVES = {
    "constrained_forward_dynamics": ("contact_solve",),
    "constrained_forward_dynamics_baumgarte": ("contact_solve",),
    "constrained_forward_dynamics_proximal": ("contact_proximal_solve",),
    "impulse_dynamics": ("contact_impulse",),
    "operational_space_inertia": ("contact_inertia",),
}
CHECK_TOLERANCE = 1e-6  # relative, between the two sides' check sums


def comments(text, robot):
    """The `# robot proximal_iterations X` and `# robot check FUNCTION SUM` lines both sides
    print: ({function: sum}, mean iterations)."""
    checks, iterations = {}, None
    for line in text.splitlines():
        parts = line.split()
        if len(parts) >= 4 and parts[0] == "#" and parts[1] == robot:
            if parts[2] == "check" and len(parts) == 5:
                checks[parts[3]] = float(parts[4])
            elif parts[2] == "proximal_iterations":
                iterations = float(parts[3])
    return checks, iterations


def dyngen_round(crate, args, env, core, target_dir, robot, seconds):
    """({function: median_ns}, {function: check sum}, mean proximal iterations) of one criterion
    run of a robot's contacts bench; only estimates written by this run are read."""
    start, stderr = criterion_run(crate, args, env, core, f"^{re.escape(robot)}/.*/generated$", seconds)
    rows = {quantity: ns for (_, quantity), ns in fresh_medians(target_dir, [robot], start).items()}
    checks, iterations = comments(stderr, robot)
    return rows, checks, iterations


def relative_difference(a, b):
    return None if a is None or b is None else abs(a - b) / max(abs(a), abs(b), 1e-300)


def main():
    args, sides, envs, anchor_env = solo12_and_g1_setup(
        __doc__.split("\n\n")[0], "contacts/build/bench_contacts", "contacts", G1_CRATE)
    robots, builds = args.robots, args.builds
    pin_cmd = ["taskset", "-c", str(args.core), str(args.anchor), str(args.anchor.parent / "models"), *robots]
    load_start = os.getloadavg()
    rounds = []
    anchor_notes, dyngen_notes = {}, {}
    for r in range(args.rounds):
        print(f"round {r + 1}/{args.rounds}", file=sys.stderr)
        out = subprocess.run(pin_cmd, env=anchor_env, check=True, capture_output=True, text=True).stdout
        pin = {(robot, fn): ns for (robot, fn), ns in anchor_rows(out, robots).items()}
        if r == 0:
            anchor_notes = {robot: comments(out, robot) for robot in robots}
        ours = {}
        for robot in robots:
            for build in builds:
                crate, cargo_args, target = sides[(robot, build)]
                times, checks, iterations = dyngen_round(crate, cargo_args, envs[(robot, build)], args.core,
                                                         target, robot, args.measurement_time)
                ours[build] = {**ours.get(build, {}), **{(robot, fn): ns for fn, ns in times.items()}}
                dyngen_notes.setdefault(robot, (checks, iterations))
        rounds.append((pin, ours))
        if r == 0:
            warn_missing([(robot, fn) for robot in robots for fn in FUNCTIONS], pin, ours)

    print(one_anchor_head(load_start, args, ["robot", "function", "Pinocchio"], "check sums agree"))
    missed = []
    for robot in robots:
        theirs_checks, _ = anchor_notes.get(robot, ({}, None))
        ours_checks, _ = dyngen_notes.get(robot, ({}, None))
        for function in FUNCTIONS:
            pin = [p.get((robot, function)) for p, _ in rounds]
            row = f"| {robot} | `{function}` | {fmt(med(pin))} |"
            for b in builds:
                ours = [o[b].get((robot, function)) for _, o in rounds]
                ratio = med([p / d for p, d in zip(pin, ours) if p and d])
                low = ratio is not None and ratio < ONE_ANCHOR_FLOOR
                if low:
                    missed.append(f"{robot} {function} ({b}): {ratio:.2f}×")
                row += f" {fmt(med(ours))} | {fmt(ratio, 2, '×')}{' **missed**' if low else ''} |"
            difference = relative_difference(theirs_checks.get(function), ours_checks.get(function))
            agree = ("–" if difference is None else "yes" if difference <= CHECK_TOLERANCE
                     else f"**no** ({difference:.1e})")
            print(row + f" {agree} |")
    if missed:
        print(f"\nBelow {ONE_ANCHOR_FLOOR:g}×: " + "; ".join(missed))

    print("\nProximal iterations per solve (mean over the states): "
          + "; ".join(f"{robot} Pinocchio {fmt(anchor_notes.get(robot, ({}, None))[1], 2)}, "
                      f"dyngen {fmt(dyngen_notes.get(robot, ({}, None))[1], 2)}" for robot in robots))
    build = builds[0]
    print(f"\nWhere each solve's time goes (dyngen {build}, ns): the generated call it makes, "
          "from the configuration, and the rest (the runtime's: the checks of the pivots and the "
          "residual, the Baumgarte terms, iterations past those of the call).\n")
    print("| robot | function | total | " + " | ".join(f"`{p}`" for p in PIECES) + " | rest |")
    print("|---|---|---:|" + "---:|" * len(PIECES) + "---:|")
    for robot in robots:
        time_of = lambda fn: med([o[build].get((robot, fn)) for _, o in rounds])
        for solve, pieces in SOLVES.items():
            total = time_of(solve)
            cells = [fmt(time_of(p)) if p in pieces else "" for p in PIECES]
            used = [time_of(p) for p in pieces]
            rest = total - sum(used) if total is not None and None not in used else None
            print(f"| {robot} | `{solve}` | {fmt(total)} | " + " | ".join(cells) + f" | {fmt(rest)} |")

    if args.record:
        rows = []
        for robot in robots:
            for function in FUNCTIONS:
                pin = med([p.get((robot, function)) for p, _ in rounds])
                for b in builds:
                    ns = med([o[b].get((robot, function)) for _, o in rounds])
                    if ns is not None:
                        rows.append({"build": b, "robot": robot, "function": function, "form": "value",
                                     "dyngen_ns": number(ns), "pinocchio_ns": number(pin)})
        record_rows(args.record, args.machine, args.date, rows)


if __name__ == "__main__":
    main()
