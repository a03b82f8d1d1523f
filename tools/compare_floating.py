#!/usr/bin/env python3
"""Side by side: dyngen's generated dynamics of Solo-12 and the Unitree G1 on a free flyer,
numeric Pinocchio 4.1 and Pinocchio 4.1 generated to C by CppADCodeGen, interleaved, pinned
to one core; prints a Markdown table.

For developers (not CI). The dyngen side is `generated/benches/common/floating.rs`, timed for
Solo-12 by `cargo bench -p dyngen-generated --bench floating` and for the G1 by the crate
`tools/anchors/floating-cg/dyngen/` (the G1 is not a committed robot: its build script generates
it, with its derivatives); both anchors are the C++ program of `tools/anchors/floating-cg/`
(build it first with its `build.sh`, see its README.md), run once per side:

    tools/anchors/floating-cg/build.sh
    tools/compare_floating.py                          # 3 rounds, dyngen built native
    tools/compare_floating.py --rounds 1 --measurement-time 0.2     # a smoke run
    tools/compare_floating.py --anchor tools/anchors/floating-cg/build/bench_floating_cg_O3

Each round runs the anchor's numeric side, its CppADCodeGen side, then each robot's dyngen
bench (criterion's medians read back from its JSON estimates), one after the other, all pinned
with `taskset -c CORE`. All time each call over the same 256 random states (the SplitMix64
stream of seed 18); the anchor has checked, before timing, that the generated C agrees with
numeric Pinocchio. Times are medians over the rounds; a ratio is the median of the per-round
ratios.

Run it on an otherwise idle machine: the two vCPUs behave like SMT siblings, so a compile on
the other one slows a benchmark 1.3-2x (BENCHMARKS.md). `--record benchmarks/results.csv
--machine KIND` appends the run's medians to the results file BENCHMARKS.md's tables are
rendered from (`cargo xtask bench-render`), both anchors beside dyngen. Standard library only;
reuses tools/compare_anchors.py's helpers.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_anchors import (ONE_ANCHOR_FLOOR, ROOT, anchor_rows,  # noqa: E402
                             criterion_run, fmt, fresh_medians, med, number, record_rows,
                             solo12_and_g1_setup, warn_missing)

G1_CRATE = ROOT / "tools" / "anchors" / "floating-cg" / "dyngen"
SIDES = ("pinocchio", "cppadcg")
# The anchor's function (Pinocchio's algorithm) -> dyngen's criterion group, in table order.
FUNCTIONS = [
    ("crba", "mass_matrix"),
    ("coriolis", "coriolis"),
    ("gravity", "gravity"),
    ("rnea", "rnea"),
    ("aba", "aba"),
    ("minv", "minv"),
    ("rnea_derivatives", "rnea_derivatives"),
    ("aba_derivatives", "aba_derivatives"),
    ("ccrba", "ccrba"),
]
# The criterion ids of a group: by value, and written into a kept `ResultBuffer` where there is
# one (`generated_into`).
FORMS = {"generated": "value", "generated_into": "into"}


def dyngen_round(crate, args, env, core, target_dir, robot, seconds):
    """{(function group, criterion id): median_ns} of one criterion run of a robot's floating
    bench, the table's groups only; only estimates written by this run are read."""
    groups = "|".join(re.escape(group) for _, group in FUNCTIONS)
    start, _ = criterion_run(crate, args, env, core, f"^{re.escape(robot)}/({groups})/generated(_into)?$", seconds)
    rows = {}
    for bench_id in FORMS:
        for (_, group), ns in fresh_medians(target_dir, [robot], start, bench_id).items():
            rows[(group, bench_id)] = ns
    return rows


def main():
    args, sides, envs, anchor_env = solo12_and_g1_setup(
        __doc__.split("\n\n")[0], "floating-cg/build/bench_floating_cg_native", "floating", G1_CRATE)
    robots, builds = args.robots, args.builds
    models = args.anchor.parent / "models"
    load_start = os.getloadavg()
    rounds = []
    for r in range(args.rounds):
        print(f"round {r + 1}/{args.rounds}", file=sys.stderr)
        anchors = {}
        for side in SIDES:
            cmd = ["taskset", "-c", str(args.core), str(args.anchor), str(models), "--side", side, *robots]
            out = subprocess.run(cmd, env=anchor_env, check=True, capture_output=True, text=True).stdout
            anchors[side] = anchor_rows(out, robots)
        ours = {}
        for robot in robots:
            for build in builds:
                crate, cargo_args, target = sides[(robot, build)]
                times = dyngen_round(crate, cargo_args, envs[(robot, build)], args.core, target, robot,
                                     args.measurement_time)
                ours.setdefault(build, {}).update({(robot, group, bench_id): ns
                                                   for (group, bench_id), ns in times.items()})
        rounds.append((anchors, ours))
        if r == 0:
            keys = [(robot, fn) for robot in robots for fn, _ in FUNCTIONS]
            by_function = {b: {(robot, fn): o.get((robot, group, "generated")) for robot in robots
                               for fn, group in FUNCTIONS if (robot, group, "generated") in o}
                           for b, o in ours.items()}
            warn_missing(keys, anchors["pinocchio"], by_function)
            for key in keys:
                if key not in anchors["cppadcg"]:
                    print(f"warning: no CppADCodeGen time for {' '.join(key)}", file=sys.stderr)

    load = os.getloadavg()
    print(f"Load average at the start: {load_start[0]:.2f} {load_start[1]:.2f} {load_start[2]:.2f}, "
          f"at the end: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; {args.rounds} interleaved rounds on "
          f"core {args.core}, {args.measurement_time:g} s per function; medians in ns; ratios are "
          f"medians of per-round ratios; CppADCodeGen: {args.anchor.name}.\n")
    header = "| robot | function | Pinocchio | CppADCodeGen | Pinocchio / CppADCodeGen |"
    rule = "|---|---|---:|---:|---:|"
    for b in builds:
        header += (f" dyngen {b} | Pinocchio / dyngen {b} (≥ {ONE_ANCHOR_FLOOR:g}) |"
                   f" CppADCodeGen / dyngen {b} |")
        rule += "---:|---:|---:|"
    print(header)
    print(rule)

    def side(name, robot, fn):
        return [a[name].get((robot, fn)) for a, _ in rounds]

    def ratio(a, b):
        return med([x / y for x, y in zip(a, b) if x and y])

    records = []
    for robot in robots:
        for fn, group in FUNCTIONS:
            pin, cg = side("pinocchio", robot, fn), side("cppadcg", robot, fn)
            for bench_id, form in FORMS.items():
                ours = {b: [o[b].get((robot, group, bench_id)) for _, o in rounds] for b in builds}
                if bench_id != "generated" and not any(any(v) for v in ours.values()):
                    continue
                name = f"{fn} / `{group}`" + ("" if form == "value" else " `_into`")
                row = f"| {robot} | {name} | {fmt(med(pin))} | {fmt(med(cg))} | {fmt(ratio(pin, cg), 2, '×')} |"
                for b in builds:
                    rp = ratio(pin, ours[b])
                    low = rp is not None and rp < ONE_ANCHOR_FLOOR
                    row += (f" {fmt(med(ours[b]))} | {fmt(rp, 2, '×')}{' **missed**' if low else ''} |"
                            f" {fmt(ratio(cg, ours[b]), 2, '×')} |")
                    if med(ours[b]) is not None:
                        records.append({"build": b, "robot": robot, "function": group, "form": form,
                                        "dyngen_ns": number(med(ours[b])), "pinocchio_ns": number(med(pin)),
                                        "cppadcg_ns": number(med(cg))})
                print(row)
    if args.record:
        record_rows(args.record, args.machine, args.date, records)


if __name__ == "__main__":
    main()
