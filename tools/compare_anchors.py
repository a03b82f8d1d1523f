#!/usr/bin/env python3
"""Side by side: dyngen's generated code, numeric Pinocchio 4.1 and Pinocchio's algorithms
generated to C by CppADCodeGen, interleaved, pinned to one core; prints a Markdown table.

For developers (not CI). The two Pinocchio programs are C++ benchmarks kept outside this
repository (built with their own notes: a pip venv with pin 4.1.0 and example-robot-data
6.0.0, then g++ -O3 -march=native); point at their directories:

    tools/compare_anchors.py --pinocchio ANCHORS/pinocchio --cppadcg ANCHORS/pinocchio-cg
    tools/compare_anchors.py ... --robots panda ur5 panda_rounded

`--robots` picks the committed robots (default: panda ur5); each needs a row of that name in
the numeric anchor's robots.txt and in the CppADCodeGen anchor's build (`ROBOTS="panda ur5
panda_rounded" ./build.sh`), except xarm7_snapped, whose anchor rows are xarm7's (the file as
written). panda_rounded is the Panda with every `rpy` rounded to 4 decimals:
dyngen generates it with `snap_angles: 1e-4`, the anchors read the rounded URDF as written
(BENCHMARKS.md, "How to reproduce").

Both print `robot nq nv function median_ns min_ns` rows, timing each call over 256
precomputed random states, as `cargo bench -p dyngen-generated` does. Each round runs the
three programs one after the other on the same core; ratios are medians of per-round ratios.
Run it on an otherwise idle machine: the two vCPUs of our machines behave like SMT siblings, so
a compile on the other one slows a benchmark 1.3-2x.

Rows marked `_into` time a function's `_into` form: its result written into a `ResultBuffer`
kept between calls, as Pinocchio writes into the `Data` it is given (dyngen's by-value row above
it zeroes and returns a fresh result each call).

Standard library only (no pip).
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_ROBOTS = ("panda", "ur5")
# Anchor function -> dyngen criterion group -> the generated function that group times (whose
# code size is reported), in table order.
FUNCTIONS = [
    ("fk", "fk", "forward_kinematics"),
    ("jacobian", "jacobian", "jacobian"),
    ("jacobian_dot", "jacobian_dot", "jacobian_dot"),
    ("crba", "mass_matrix", "mass_matrix"),
    ("coriolis", "coriolis", "coriolis_matrix"),
    ("gravity", "gravity", "gravity"),
    ("rnea", "rnea", "inverse_dynamics"),
    ("regressor", "torque_regressor", "torque_regressor"),
    # Pinocchio has one regressor (torque form); dyngen's other regressors against it.
    ("regressor", "regressor", "regressor"),
    ("regressor", "base_torque_regressor", "base_torque_regressor"),
    ("regressor", "base_regressor", "base_regressor"),
    ("aba", "aba", "forward_dynamics"),
    ("minv", "minv", "mass_matrix_inverse"),
    ("rnea_derivatives", "rnea_derivatives", "inverse_dynamics_derivatives"),
    ("aba_derivatives", "aba_derivatives", "forward_dynamics_derivatives"),
]
# Groups that also time the `_into` form (criterion id `generated_into`: the result written into a
# `ResultBuffer` kept between calls, as Pinocchio writes into its `Data`): a row each.
INTO = {"mass_matrix", "coriolis", "torque_regressor", "regressor", "base_torque_regressor",
        "base_regressor", "minv", "rnea_derivatives", "aba_derivatives"}


def timed_rows():
    """(anchor function, criterion group, criterion id) of every table row: each function by
    value, then its `_into` form where it has one."""
    for fn, group, _ in FUNCTIONS:
        yield fn, group, "generated"
        if group in INTO:
            yield fn, group, "generated_into"


# Several states per call: (criterion group, lane ids), per state against the single call.
BATCHES = [("rnea", ("generated_lanes4", "generated_lanes8")),
           ("base_torque_regressor", ("generated_lanes4", "generated_lanes8"))]
FLOOR_PINOCCHIO, FLOOR_CG, FLOOR_DEFAULT = 5.0, 2.0, 1.2
# A committed robot generated from a file the anchors read as written: the anchors' row is the
# file's (Pinocchio has no snapping).
ANCHOR_ROBOT = {"xarm7_snapped": "xarm7"}


def anchor_name(robot):
    return ANCHOR_ROBOT.get(robot, robot)


def run(cmd, cwd=None, env=None):
    out = subprocess.run(cmd, cwd=cwd, env=env, check=True, capture_output=True, text=True)
    return out.stdout


def anchor_rows(text, robots):
    """{(robot, function): median_ns} from an anchor's output."""
    rows = {}
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 6 and parts[0] in robots and not line.startswith("#"):
            rows[(parts[0], parts[3])] = float(parts[4])
    return rows


def cargo_env(target_dir, native):
    env = dict(os.environ)
    env["CARGO_TARGET_DIR"] = str(target_dir)
    env["RUSTFLAGS"] = "-C target-cpu=native" if native else ""
    return env


def dyngen_build(env, root=ROOT):
    """Builds the benches of the repository at `root`; returns their executables."""
    cmd = ["cargo", "bench", "-p", "dyngen-generated", "--bench", "dynamics",
           "--bench", "forward_dynamics", "--bench", "floating", "--no-run",
           "--message-format=json-render-diagnostics"]
    out = subprocess.run(cmd, cwd=root, env=env, check=True, stdout=subprocess.PIPE, text=True).stdout
    executables = []
    for line in out.splitlines():
        message = json.loads(line) if line.startswith("{") else {}
        if message.get("reason") == "compiler-artifact" and message.get("executable"):
            executables.append(message["executable"])
    return executables


def code_sizes(executables, robots):
    """{(robot, group): bytes} of machine code of each timed generated function (its chunk
    functions included), from `nm -S`: a function larger than the level-1 instruction cache is
    fetched from the level-2 cache on every call of a loop that runs only it (BENCHMARKS.md)."""
    group_of = {function: group for _, group, function in FUNCTIONS}
    # The trait method `<dyngen_generated::panda::Panda as …>::f`, or a chunk of it
    # `dyngen_generated::panda::f_part0`.
    symbol = re.compile(r"^(?:<dyngen_generated::(\w+)::\w+ as .*>::(\w+)"
                        r"|dyngen_generated::(\w+)::(\w+?)_part\d+)$")
    sizes = {}
    for exe in executables:
        try:
            table = run(["nm", "-S", "--demangle", exe])
        except (OSError, subprocess.CalledProcessError):
            return {}
        for line in table.splitlines():
            parts = line.split(None, 3)
            match = symbol.match(parts[3]) if len(parts) == 4 else None
            if not match:
                continue
            robot, function = (match.group(1), match.group(2)) if match.group(1) else (match.group(3), match.group(4))
            if robot in robots and function in group_of:
                key = (robot, group_of[function])
                sizes[key] = sizes.get(key, 0) + int(parts[1], 16)
    return sizes


def instruction_cache_bytes():
    """The level-1 instruction cache of CPU 0 (Linux sysfs), or None."""
    for index in Path("/sys/devices/system/cpu/cpu0/cache").glob("index*"):
        try:
            if (index / "level").read_text().strip() == "1" and (index / "type").read_text().strip() == "Instruction":
                size = (index / "size").read_text().strip()
                return int(size.rstrip("K")) * 1024 if size.endswith("K") else int(size)
        except OSError:
            continue
    return None


def bench_filter(robots, by_value_only=False):
    """Criterion's filter (a regex) for the generated code of these robots (only the by-value
    rows when `by_value_only`): `^(panda)/` does not match `panda_rounded/...`."""
    forms = "" if by_value_only else "(_lanes[48]|_into)?"
    return "^(" + "|".join(re.escape(r) for r in robots) + ")/.*/generated" + forms + "$"


def split_group(directory, bench_dirs, robots):
    """(robot, quantity) of a criterion group directory: from the group id criterion records
    ("panda_rounded/fk"), since the directory name ("panda_rounded_fk") is ambiguous; else the
    longest robot name the directory starts with."""
    for bench in bench_dirs:
        info = bench / "new" / "benchmark.json"
        if info.is_file():
            robot, sep, quantity = json.loads(info.read_text()).get("group_id", "").partition("/")
            if sep:
                return robot, quantity
    for robot in sorted(robots, key=len, reverse=True):
        if directory.name.startswith(robot + "_"):
            return robot, directory.name[len(robot) + 1:]
    return None, None


def dyngen_round(env, core, target_dir, robots, seconds, root=ROOT, by_value_only=False):
    """{(robot, group, id): median_ns} of one run of the benches (each function measured for
    `seconds`, or criterion's own time when None; only the by-value rows when `by_value_only`)."""
    timing = []
    if seconds is not None:
        timing = ["--warm-up-time", f"{seconds / 3:g}", "--measurement-time", f"{seconds:g}"]
    for bench in ("dynamics", "forward_dynamics", "floating"):
        cmd = ["taskset", "-c", str(core), "cargo", "bench", "-q", "-p", "dyngen-generated",
               "--bench", bench, "--", bench_filter(robots, by_value_only), *timing]
        run(cmd, cwd=root, env=env)
    rows = {}
    criterion = Path(target_dir) / "criterion"
    for group in criterion.iterdir():
        if not group.is_dir():
            continue
        bench_dirs = [b for b in group.iterdir() if b.is_dir()]
        robot, quantity = split_group(group, bench_dirs, robots)
        if robot not in robots:
            continue
        for bench in bench_dirs:
            estimates = bench / "new" / "estimates.json"
            if estimates.is_file():
                median = json.loads(estimates.read_text())["median"]["point_estimate"]
                rows[(robot, quantity, bench.name)] = median
    return rows


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fmt(x, digits=0, suffix=""):
    return "–" if x is None else f"{x:.{digits}f}{suffix}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pinocchio", type=Path, required=True, help="numeric Pinocchio anchor directory")
    ap.add_argument("--cppadcg", type=Path, required=True, help="Pinocchio + CppADCodeGen anchor directory")
    ap.add_argument("--robots", nargs="+", default=list(DEFAULT_ROBOTS), metavar="ROBOT",
                    help="committed robots to compare, e.g. panda ur5 panda_rounded "
                         f"(default: {' '.join(DEFAULT_ROBOTS)})")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--core", type=int, default=1)
    ap.add_argument("--measurement-time", type=float, metavar="SECONDS",
                    help="criterion's measurement time per dyngen function (warm-up a third of it): "
                         "shorter rounds, so more of them fit; every round is a new process, whose "
                         "stack placement and host noise differ (default: the benches' own)")
    ap.add_argument("--default-build", action="store_true",
                    help="also time dyngen built without target-cpu (the default build)")
    args = ap.parse_args()
    robots = list(dict.fromkeys(args.robots))
    unknown = [r for r in robots if not (ROOT / "robots" / f"{r}.yaml").is_file()]
    if unknown:
        ap.error(f"not a committed robot (robots/<name>.yaml): {', '.join(unknown)}")

    native_dir = ROOT / "target" / "bench-native"
    default_dir = ROOT / "target" / "bench-default"
    builds = [("native", native_dir, cargo_env(native_dir, True))]
    if args.default_build:
        builds.append(("default", default_dir, cargo_env(default_dir, False)))
    executables = {name: dyngen_build(env) for name, _, env in builds}
    sizes = code_sizes(executables["native"], robots)
    l1i = instruction_cache_bytes()

    anchors = list(dict.fromkeys(anchor_name(r) for r in robots))
    pin_cmd = ["taskset", "-c", str(args.core), str(args.pinocchio / "build" / "bench_native"),
               "robots.txt", "build/models", *anchors]
    cg_cmd = ["taskset", "-c", str(args.core), str(args.cppadcg / "build" / "bench_cg_native"), *anchors]
    rounds = []
    for r in range(args.rounds):
        print(f"round {r + 1}/{args.rounds}", file=sys.stderr)
        pin = anchor_rows(run(pin_cmd, cwd=args.pinocchio), anchors)
        cg = anchor_rows(run(cg_cmd, cwd=args.cppadcg), anchors)
        ours = {name: dyngen_round(env, args.core, d, robots, args.measurement_time) for name, d, env in builds}
        rounds.append((pin, cg, ours))
        if r == 0:
            for robot in robots:
                for anchor, rows, fix in (
                        ("numeric Pinocchio", pin, "a row in robots.txt and build/models/<robot>.txt"),
                        ("CppADCodeGen", cg, "ROBOTS=\"... <robot>\" ./build.sh")):
                    if not any(k[0] == anchor_name(robot) for k in rows):
                        print(f"warning: {anchor} printed no row for {robot} ({fix})", file=sys.stderr)

    load = os.getloadavg()
    cache = f"; level-1 instruction cache {l1i // 1024} KiB" if l1i else ""
    print(f"Load average at the end: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; "
          f"{args.rounds} interleaved rounds on core {args.core}; medians in ns; ratios are medians "
          f"of per-round ratios{cache}.\n")
    header = "| robot | function | Pinocchio | CppADCodeGen | dyngen native |"
    rule = "|---|---|---:|---:|---:|"
    if args.default_build:
        header += " dyngen default | default / native |"
        rule += "---:|---:|"
    header += f" Pinocchio / dyngen (≥ {FLOOR_PINOCCHIO:g}) | CppADCodeGen / dyngen (≥ {FLOOR_CG:g}) |"
    rule += "---:|---:|"
    if sizes:
        header += " native code (KB) |"
        rule += "---:|"
    print(header)
    print(rule)
    for robot in robots:
        for fn, group, bench_id in timed_rows():
            key = (robot, group, bench_id)
            native = [o["native"].get(key) for _, _, o in rounds]
            if bench_id != "generated" and not any(native):
                continue
            pin = [p.get((anchor_name(robot), fn)) for p, _, _ in rounds]
            cg = [c.get((anchor_name(robot), fn)) for _, c, _ in rounds]
            ratio = lambda a, b: med([x / y for x, y in zip(a, b) if x and y])
            rp, rc = ratio(pin, native), ratio(cg, native)
            mark = lambda r, floor: fmt(r, 2, "×") + ("" if r is None or r >= floor else " **missed**")
            form = "" if bench_id == "generated" else " `_into`"
            row = f"| {robot} | {fn} / `{group}`{form} | {fmt(med(pin))} | {fmt(med(cg))} | {fmt(med(native))} |"
            if args.default_build:
                default = [o["default"].get(key) for _, _, o in rounds]
                rd = ratio(default, native)
                row += f" {fmt(med(default))} | {fmt(rd, 2, '×')}{'' if rd is None or rd <= FLOOR_DEFAULT else ' **missed**'} |"
            row += f" {mark(rp, FLOOR_PINOCCHIO)} | {mark(rc, FLOOR_CG)} |"
            if sizes:
                size = sizes.get((robot, group)) if bench_id == "generated" else None
                over = size is not None and l1i is not None and size > l1i
                row += f" {fmt(size / 1000 if size else None, 1)}{' (over L1i)' if over else ''} |"
            print(row)
    print("\nSeveral states per call (dyngen native, ns per state; throughput against one state per call):\n")
    print("| robot | function | one per call | lanes | per state | throughput ratio |")
    print("|---|---|---:|---:|---:|---:|")
    for robot in robots:
        for group, ids in BATCHES:
            single = [o["native"].get((robot, group, "generated")) for _, _, o in rounds]
            for lane_id in ids:
                width = int(lane_id.removeprefix("generated_lanes"))
                batch = [o["native"].get((robot, group, lane_id)) for _, _, o in rounds]
                per_state = [b / width if b else None for b in batch]
                ratio = med([s / p for s, p in zip(single, per_state) if s and p])
                print(f"| {robot} | {group} | {fmt(med(single))} | {width} | {fmt(med(per_state))} | "
                      f"{fmt(ratio, 2, '×')} |")


if __name__ == "__main__":
    main()
