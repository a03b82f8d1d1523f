#!/usr/bin/env python3
"""Two revisions of the repository side by side: the generated crate's benchmarks built at each
revision (a git worktree each), by default and with `-C target-cpu=native`, all builds timed in
interleaved rounds pinned to one core; prints, per robot and function, every build's median and
the old revision's time over the new one's per profile (above 1: the new one is faster).

For developers (not CI): four release builds of the benchmarks (a few minutes each on two
cores), and the timing wants an otherwise idle machine. A revision is anything `git worktree
add` takes; `--new` defaults to the working tree as it is, uncommitted changes to tracked files
included (`git add` a new file for it to be copied).

    tools/compare_revisions.py --old HEAD~1 --robots panda ur5 solo12 --rounds 3

Standard library only (no pip). Shares its build and timing with compare_anchors.py.
"""

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from build_spread import build_and_time, copy_repository  # noqa: E402
from compare_anchors import cargo_env, fmt, med, timed_rows  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
PROFILES = ("default", "native")


def checkout(revision, destination):
    """The tree of `revision` at `destination` (a detached worktree), or the working tree's
    tracked files as they are when `revision` is None."""
    if revision is None:
        copy_repository(destination)
    else:
        subprocess.run(["git", "worktree", "add", "--detach", "--force", str(destination), revision],
                       cwd=ROOT, check=True, capture_output=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--old", required=True, metavar="REVISION")
    ap.add_argument("--new", default=None, metavar="REVISION", help="default: the working tree")
    ap.add_argument("--robots", nargs="+", default=["panda", "ur5"], metavar="ROBOT")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--core", type=int, default=1)
    ap.add_argument("--measurement-time", type=float, default=1.0, metavar="SECONDS")
    args = ap.parse_args()

    scratch = Path(tempfile.mkdtemp(prefix="dyngen-revisions-"))
    trees = {"old": scratch / "old", "new": scratch / "new"}
    try:
        checkout(args.old, trees["old"])
        checkout(args.new, trees["new"])
        builds = []  # (label, tree, target dir, environment)
        for side, tree in trees.items():
            for profile in PROFILES:
                target = tree / "target" / profile
                builds.append((f"{side} {profile}", tree, target, cargo_env(target, profile == "native")))
        rounds = build_and_time(builds, args.robots, args.rounds, args.core, args.measurement_time)
    finally:
        for tree in trees.values():
            subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, capture_output=True)
        shutil.rmtree(scratch, ignore_errors=True)

    labels = [label for label, *_ in builds]
    print(f"old {args.old}, new {args.new or 'the working tree'}; {args.rounds} interleaved rounds on core "
          f"{args.core}; medians in ns; old / new above 1 where the new one is faster.\n")
    print("| robot | function | " + " | ".join(labels) + " | " + " | ".join(f"old / new {p}" for p in PROFILES) + " |")
    print("|---|---|" + "---:|" * (len(labels) + len(PROFILES)))
    for robot in args.robots:
        for _, group, bench_id in timed_rows():
            key = (robot, group, bench_id)
            medians = {label: med([rnd[label].get(key) for rnd in rounds]) for label in labels}
            if all(v is None for v in medians.values()):
                continue
            ratios = [fmt(medians[f"old {p}"] / medians[f"new {p}"], 2, "×")
                      if medians[f"old {p}"] and medians[f"new {p}"] else "–" for p in PROFILES]
            form = "" if bench_id == "generated" else " `_into`"
            print(f"| {robot} | `{group}`{form} | " + " | ".join(fmt(medians[l]) for l in labels) +
                  " | " + " | ".join(ratios) + " |")


if __name__ == "__main__":
    main()
