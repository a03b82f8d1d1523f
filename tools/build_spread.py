#!/usr/bin/env python3
"""How much the speed of the same generated code depends on the build: the repository copied to
several paths of different lengths, the generated crate's benchmarks built in each copy by
default and with `-C target-cpu=native`, all builds timed in interleaved rounds pinned to one
core; prints, per robot and function, every build's median over its launches and its best
launch, the spread (slowest over fastest build of each profile) and default over native, and
how far apart two launches of one build ran.

For developers (not CI): every copy is a full release build of the benchmarks (a few minutes
each on two cores), and the timing wants an otherwise idle machine.

    tools/build_spread.py --copies 5 --robots panda ur5 xarm7 --rounds 3 --measurement-time 1

Standard library only (no pip). Shares its build and timing with compare_anchors.py.
"""

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_anchors import FUNCTIONS, cargo_env, dyngen_build, dyngen_round, fmt, med  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
# Builds within this factor of the fastest build of the same profile, and default builds
# within this factor of native, count as the same speed.
SPREAD_FLOOR, DEFAULT_FLOOR = 1.2, 1.2


def copy_repository(destination):
    """The tracked files of this checkout at `destination` (a clean tree, as a user has it)."""
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True,
                           capture_output=True).stdout.decode().split("\0")
    for name in filter(None, files):
        target = destination / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, target)


def build_and_time(builds, robots, rounds, core, seconds):
    """Builds every (label, tree, target dir, environment) of `builds`, then times them all in
    `rounds` interleaved rounds pinned to `core`: per round {label: {(robot, group, id): ns}}."""
    for label, tree, _, env in builds:
        print(f"building {label} in {tree}", file=sys.stderr)
        dyngen_build(env, root=tree)
    timed = []
    for r in range(rounds):
        print(f"round {r + 1}/{rounds}", file=sys.stderr)
        # The tables report the by-value rows only: the `_into` and lane rows would double a round.
        timed.append({label: dyngen_round(env, core, target, robots, seconds, root=tree,
                                          by_value_only=True)
                      for label, tree, target, env in builds})
    return timed


def print_table(rounds, labels, robots, reduce, launches=False):
    """A Markdown table: per robot and function, each build's launches reduced by `reduce`, the
    spread of each profile's builds and default over native (and, with `launches`, the largest
    ratio between two launches of one build)."""
    mark = lambda x, floor: fmt(x, 2, "×") + ("" if x is None or x <= floor else " **over**")
    extra = " launches of one build |" if launches else ""
    print("| robot | function | " + " | ".join(labels) +
          " | spread default | spread native | default / native |" + extra)
    print("|---|---|" + "---:|" * (len(labels) + 3 + (1 if launches else 0)))
    for robot in robots:
        for _, group, _ in FUNCTIONS:
            key = (robot, group, "generated")
            runs = {label: [v for v in (rnd[label].get(key) for rnd in rounds) if v] for label in labels}
            values = {label: reduce(v) if v else None for label, v in runs.items()}
            by_profile = {p: [v for l, v in values.items() if l.startswith(p) and v] for p in ("default", "native")}
            spread = {p: (max(v) / min(v) if v else None) for p, v in by_profile.items()}
            ratio = (med(by_profile["default"]) / med(by_profile["native"])
                     if by_profile["default"] and by_profile["native"] else None)
            row = (f"| {robot} | `{group}` | " + " | ".join(fmt(values[l]) for l in labels) +
                   f" | {mark(spread['default'], SPREAD_FLOOR)} | {mark(spread['native'], SPREAD_FLOOR)} |"
                   f" {mark(ratio, DEFAULT_FLOOR)} |")
            if launches:
                within = [max(v) / min(v) for v in runs.values() if v]
                row += f" {fmt(max(within) if within else None, 2, '×')} |"
            print(row)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--copies", type=int, default=5)
    ap.add_argument("--robots", nargs="+", default=["panda", "ur5"], metavar="ROBOT")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--core", type=int, default=1)
    ap.add_argument("--measurement-time", type=float, default=1.0, metavar="SECONDS")
    ap.add_argument("--keep", action="store_true", help="keep the copies (their paths are printed)")
    args = ap.parse_args()

    scratch = Path(tempfile.mkdtemp(prefix="dyngen-spread-"))
    builds = []  # (label, repository copy, target dir, environment)
    for k in range(args.copies):
        # Paths of different lengths: symbol names, panic locations and section layout move.
        copy = scratch / ("c" * (k + 1)) / f"dyngen-copy-{k}"
        copy_repository(copy)
        for native in (False, True):
            profile = "native" if native else "default"
            target = copy / "target"
            builds.append((f"{profile} {k}", copy, target / profile, cargo_env(target / profile, native)))
    rounds = build_and_time(builds, args.robots, args.rounds, args.core, args.measurement_time)

    labels = [label for label, *_ in builds]
    print(f"{args.copies} copies at paths of different lengths, built by default and native; "
          f"{args.rounds} interleaved rounds on core {args.core}; ns.\n")
    print("Median of each build's launches:\n")
    print_table(rounds, labels, args.robots, med)
    # Where the launches of one binary disagree more than the builds do, the speed follows the
    # launch, not the build: each build's best launch is what the build itself can do.
    print("\nBest launch of each build, and the largest ratio between two launches of one build:\n")
    print_table(rounds, labels, args.robots, min, launches=True)
    if args.keep:
        print(f"\ncopies kept in {scratch}", file=sys.stderr)
    else:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
