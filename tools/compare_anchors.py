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
written: Pinocchio has no snapping).

panda_rounded is the Panda with every `rpy` rounded to 4 decimals, generated with
`snap_angles: 1e-4`; the anchors read the rounded URDF as written: copy
robots/urdf/panda_rounded.urdf to panda_description/urdf/ under example-robot-data's robots/,
add the row `panda_rounded panda_description/urdf/panda_rounded.urdf panda_hand_tcp
panda_finger_joint1,panda_finger_joint2` to the numeric anchor's robots.txt, make its model with
the anchor's build/urdf_to_model, and rebuild the CppADCodeGen anchor with the robot in ROBOTS.

Floating bases (solo12): tools/compare_floating.py sets Solo-12 and the G1 beside both anchors
of tools/anchors/floating-cg/ (numeric Pinocchio and CppADCodeGen, built in this repository).
Here, the numeric anchor times any model it is given as a text archive. Make a free-flyer model
with the anchor's Python environment, bounds on the base position for randomConfiguration, and
give it a row:

    /tmp/pinenv/bin/python -c "
    import pinocchio as pin
    m = pin.buildModelFromUrdf('robots/urdf/solo12.urdf', pin.JointModelFreeFlyer())
    m.lowerPositionLimit[:3] = -1; m.upperPositionLimit[:3] = 1
    m.saveToText('ANCHORS/pinocchio/build/models/solo12.txt')"
    echo 'solo12 solo_description/robots/solo12.urdf FL_FOOT -' >> ANCHORS/pinocchio/robots.txt

The humanoid (Unitree G1) is not a committed robot (every function is 13 MB of Rust): generate
it into a crate of its own (`dyngen gen g1_29dof_rev_1_0.urdf --floating-base --functions all
--frame left_ankle_roll_link -o src/g1.rs --type-name G1`), time it with a copy of
generated/benches/floating.rs, and give the anchor a free-flyer model and the row
`g1 g1_description/urdf/g1_29dof_rev_1_0.urdf left_ankle_roll_link -`.

`--record benchmarks/results.csv --machine KIND` appends the run's medians to the results file
from which `cargo xtask bench-render` renders BENCHMARKS.md's tables (its columns:
xtask/src/results.rs): a row per robot, function, form and build, the anchors' medians beside
dyngen's.

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
import csv
import datetime
import json
import os
import re
import statistics
import subprocess
import sys
import time
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
# The claim of the one-anchor comparisons (compare_frames.py, compare_contacts.py): each function
# at least 5x faster than numeric Pinocchio.
ONE_ANCHOR_FLOOR = FLOOR_PINOCCHIO
# A committed robot generated from a file the anchors read as written: the anchors' row is the
# file's (Pinocchio has no snapping).
ANCHOR_ROBOT = {"xarm7_snapped": "xarm7"}


def anchor_name(robot):
    return ANCHOR_ROBOT.get(robot, robot)


# The columns of benchmarks/results.csv, in order (xtask/src/results.rs).
RESULTS_HEADER = ["machine", "date", "build", "robot", "function", "frame", "form", "dyngen_ns",
                  "pinocchio_ns", "cppadcg_ns", "code_kb", "l1i_kib"]


def add_record_arguments(ap):
    """--record, --machine and --date, shared by the tools that write results."""
    ap.add_argument("--record", type=Path, metavar="RESULTS_CSV",
                    help="append the run's medians to this results file (benchmarks/results.csv), "
                         "from which `cargo xtask bench-render` renders BENCHMARKS.md's tables")
    ap.add_argument("--machine", metavar="KIND",
                    help='the kind of machine, as the results file names it (e.g. "AMD EPYC Zen 3 (AVX2)")')
    ap.add_argument("--date", default=datetime.date.today().isoformat(), metavar="YYYY-MM-DD",
                    help="the run's date (default: today)")


def check_record_arguments(ap, args):
    if args.record and not args.machine:
        ap.error("--record needs --machine")
    try:
        datetime.date.fromisoformat(args.date)
    except ValueError:
        ap.error(f"--date {args.date}: expected YYYY-MM-DD")


def number(x):
    """A results-file number: one decimal, empty when not measured."""
    return "" if x is None else f"{x:.1f}"


def record_rows(path, machine, date, rows):
    """Appends `rows` (dicts keyed by RESULTS_HEADER's columns; machine and date filled in here) to
    the results file, the header first when the file is new; refuses a file of other columns."""
    path = Path(path)
    text = path.read_text() if path.is_file() else ""
    if text.strip():
        header = next(csv.reader([text.splitlines()[0]]))
        if header != RESULTS_HEADER:
            sys.exit(f"error: {path}: its header is not {','.join(RESULTS_HEADER)}")
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a", newline="") as f:
        if text and not text.endswith("\n"):
            f.write("\n")
        writer = csv.writer(f, lineterminator="\n")
        if not text.strip():
            writer.writerow(RESULTS_HEADER)
        for row in rows:
            row = dict(row, machine=machine, date=date)
            writer.writerow([row.get(column, "") for column in RESULTS_HEADER])
    print(f"recorded {len(rows)} rows in {path}", file=sys.stderr)


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
    fetched from the level-2 cache on every call of a loop that runs only it
    (docs/performance-notes.md)."""
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


def fresh_medians(target_dir, robots, since, bench_id="generated"):
    """{(robot, quantity): median_ns} of the criterion id `bench_id` of every group of these
    robots whose estimates were written at `since` or later (by the run just made)."""
    rows = {}
    for group in (Path(target_dir) / "criterion").iterdir():
        if not group.is_dir():
            continue
        bench = group / bench_id
        robot, quantity = split_group(group, [bench], robots)
        estimates = bench / "new" / "estimates.json"
        if robot in robots and estimates.is_file() and estimates.stat().st_mtime >= since:
            rows[(robot, quantity)] = json.loads(estimates.read_text())["median"]["point_estimate"]
    return rows


def solo12_and_g1(builds, bench, g1_crate):
    """{(robot, build): (crate directory, cargo arguments, target directory)} of a bench timed
    on Solo-12 and the G1: Solo-12's `bench` from the repository's workspace, the G1's from its
    own crate `g1_crate` (a workspace of its own, offline: its lock file is the repository's),
    each build in its own target directory."""
    sides = {}
    for build in builds:
        sub = "bench-native" if build == "native" else ""
        sides[("solo12", build)] = (ROOT, ["-p", "dyngen-generated", "--bench", bench], ROOT / "target" / sub)
        sides[("g1", build)] = (g1_crate, ["--offline", "--bench", bench], g1_crate / "target" / sub)
    return sides


def solo12_and_g1_setup(description, anchor, bench, g1_crate):
    """What a one-anchor comparison of Solo-12 and the G1 starts with: its arguments
    (`one_anchor_arguments`), the dyngen sides of `bench` (`solo12_and_g1`), their cargo
    environments once built (`build_benches`) and the anchor's environment (its measurement
    time)."""
    args = one_anchor_arguments(description, ("solo12", "g1"), ("native", "default"), "native", anchor)
    sides = solo12_and_g1(args.builds, bench, g1_crate)
    envs = build_benches(sides, args.robots, args.builds)
    anchor_env = dict(os.environ, BENCH_SECONDS=f"{args.measurement_time:g}")
    return args, sides, envs, anchor_env


def build_benches(sides, robots, builds):
    """Builds each robot's bench in each build before the rounds, so that no round times a
    compile; returns the cargo environment of each (robot, build)."""
    envs = {}
    for robot in robots:
        for build in builds:
            crate, cargo_args, target = sides[(robot, build)]
            envs[(robot, build)] = cargo_env(target, build == "native")
            print(f"building the bench of {robot} ({build})", file=sys.stderr)
            subprocess.run(["cargo", "bench", *cargo_args, "--no-run"], cwd=crate, env=envs[(robot, build)],
                           check=True)
    return envs


def criterion_run(crate, args, env, core, pattern, seconds):
    """Runs `cargo bench ARGS` in `crate`, pinned to `core`, on the criterion ids matching
    `pattern`, each measured for `seconds` (warm-up a third of it); returns when it started (for
    `fresh_medians`) and its stderr (what the bench printed besides criterion)."""
    start = time.time()
    timing = ["--warm-up-time", f"{seconds / 3:g}", "--measurement-time", f"{seconds:g}"]
    out = subprocess.run(["taskset", "-c", str(core), "cargo", "bench", "-q", *args, "--", pattern, *timing],
                         cwd=crate, env=env, check=True, capture_output=True, text=True)
    return start, out.stderr


def one_anchor_arguments(description, robots, builds, default_build, anchor):
    """The command line of a tool that sets one anchor program beside a dyngen bench
    (compare_frames.py, compare_contacts.py, compare_floating.py): robots, rounds, core,
    measurement time, dyngen's builds, the anchor's executable (`anchor`, under tools/anchors/)
    and --record. Returns the arguments, with the robots and builds listed once each; refuses an
    anchor not built."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--robots", nargs="+", default=list(robots), choices=list(robots))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--core", type=int, default=1)
    ap.add_argument("--measurement-time", type=float, default=1.0, metavar="SECONDS",
                    help="per function, both sides (criterion's warm-up a third of it; default 1)")
    ap.add_argument("--builds", nargs="+", default=[default_build], choices=list(builds),
                    help="dyngen builds to time: default (target/) and/or native "
                         f"(target-cpu=native, as the anchor's -march=native); default: {default_build}")
    ap.add_argument("--anchor", type=Path, default=ROOT / "tools" / "anchors" / anchor,
                    help=f"the anchor's executable (default: tools/anchors/{anchor})")
    add_record_arguments(ap)
    args = ap.parse_args()
    check_record_arguments(ap, args)
    args.robots = list(dict.fromkeys(args.robots))
    args.builds = list(dict.fromkeys(args.builds))
    if not args.anchor.is_file():
        ap.error(f"no {args.anchor}: build it with {args.anchor.parent.parent / 'build.sh'}")
    return args


def warn_missing(keys, pin, ours):
    """A warning for each key (a row's name in both programs' output) that the anchor's rows
    `pin` or dyngen's `ours` ({build: rows}) lack, after a first round."""
    for key in keys:
        for side, rows in [("Pinocchio", pin)] + [(f"dyngen {b}", r) for b, r in ours.items()]:
            if key not in rows:
                print(f"warning: no {side} time for {' '.join(key)}", file=sys.stderr)


def one_anchor_head(load_start, args, columns, last):
    """The run's summary line and the table's first two lines of a one-anchor comparison: the
    `columns` (left-aligned, ending with Pinocchio's), per dyngen build its median and ratio (its
    floor, `ONE_ANCHOR_FLOOR`, in the header), and `last`."""
    load = os.getloadavg()
    summary = (f"Load average at the start: {load_start[0]:.2f} {load_start[1]:.2f} {load_start[2]:.2f}, "
               f"at the end: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; {args.rounds} interleaved rounds "
               f"on core {args.core}, {args.measurement_time:g} s per function; medians in ns; ratios are "
               f"medians of per-round ratios; dyngen build(s): {', '.join(args.builds)}.\n")
    header = "| " + " | ".join(columns) + " |"
    rule = "|" + "---|" * (len(columns) - 1) + "---:|"
    for b in args.builds:
        header += f" dyngen {b} | Pinocchio / dyngen {b} (≥ {ONE_ANCHOR_FLOOR:g}) |"
        rule += "---:|---:|"
    return "\n".join([summary, header + f" {last} |", rule + "---:|"])


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
    add_record_arguments(ap)
    args = ap.parse_args()
    check_record_arguments(ap, args)
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
    if args.record:
        record_rows(args.record, args.machine, args.date,
                    results_rows(rounds, robots, [name for name, _, _ in builds], sizes, l1i))


def results_rows(rounds, robots, builds, sizes, l1i):
    """The run as results-file rows: per robot, function, form and build, dyngen's median over
    the rounds and the anchors' beside it (none for lanes, which no anchor times)."""
    forms = [(fn, group, bench_id, "value" if bench_id == "generated" else "into")
             for fn, group, bench_id in timed_rows()]
    forms += [(None, group, lane_id, "lanes" + lane_id.removeprefix("generated_lanes"))
              for group, ids in BATCHES for lane_id in ids]
    rows = []
    for robot in robots:
        for fn, group, bench_id, form in forms:
            anchor = lambda side: med([r[side].get((anchor_name(robot), fn)) for r in rounds]) if fn else None
            for build in builds:
                ns = med([r[2][build].get((robot, group, bench_id)) for r in rounds])
                if ns is None:
                    continue
                size = sizes.get((robot, group)) if build == "native" and form == "value" else None
                rows.append({"build": build, "robot": robot, "function": group, "form": form,
                             "dyngen_ns": number(ns), "pinocchio_ns": number(anchor(0)),
                             "cppadcg_ns": number(anchor(1)), "code_kb": number(size / 1000 if size else None),
                             "l1i_kib": number(l1i / 1024 if l1i else None)})
    return rows


if __name__ == "__main__":
    main()
