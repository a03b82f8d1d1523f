"""A batch of Panda states through the compiled robot (dyngen.compile), against the Rust
per-state time × B and a Python loop over Pinocchio's per-state calls. A developer script, not
run by CI:

    python python/bench/batch.py [--states 1000] [--rust-ns inverse_dynamics=NS ...]

The Rust per-state times are this machine's, given with --rust-ns (from `cargo bench -p
dyngen-generated --bench dynamics`), else the default build's rows of
benchmarks/results.csv (another machine: say so when comparing). Pinocchio (`pip install pin`)
is optional.
"""

import argparse
import csv
import time
from pathlib import Path

import numpy as np

import dyngen

REPO = Path(__file__).resolve().parents[2]
FUNCTIONS = ["inverse_dynamics", "mass_matrix", "torque_regressor"]


def best(f, repeats=20):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def rust_ns(given):
    table = {}
    for row in csv.DictReader((REPO / "benchmarks" / "results.csv").open()):
        if row["robot"] == "panda" and row["build"] == "default" and row["form"] == "value":
            table.setdefault(row["function"], float(row["dyngen_ns"]))
    for item in given:
        name, ns = item.split("=")
        table[name] = float(ns)
    return table


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--states", type=int, default=1000)
    parser.add_argument("--rust-ns", action="append", default=[])
    args = parser.parse_args()
    b = args.states
    compiled = dyngen.compile(REPO / "robots" / "panda.yaml", functions=["regressors"])
    rng = np.random.default_rng(1)
    q, qd, qdd = (rng.uniform(-1, 1, (b, 7)) for _ in range(3))
    calls = {
        "inverse_dynamics": lambda: compiled.inverse_dynamics(q, qd, qdd),
        "mass_matrix": lambda: compiled.mass_matrix(q),
        "torque_regressor": lambda: compiled.torque_regressor(q, qd, qdd),
    }
    reference = rust_ns(args.rust_ns)
    try:
        import pinocchio as pin

        model = pin.buildModelFromUrdf(str(REPO / "robots" / "urdf" / "panda.urdf"))
        model = pin.buildReducedModel(model, [model.getJointId("panda_finger_joint1"), model.getJointId("panda_finger_joint2")], pin.neutral(model))
        data = model.createData()
        pinocchio = {
            "inverse_dynamics": lambda: [pin.rnea(model, data, q[k], qd[k], qdd[k]) for k in range(b)],
            "mass_matrix": lambda: [pin.crba(model, data, q[k]) for k in range(b)],
            "torque_regressor": lambda: [
                pin.computeJointTorqueRegressor(model, data, q[k], qd[k], qdd[k]) for k in range(b)
            ],
        }
    except ImportError:
        pinocchio = {}
        print("pinocchio not installed (pip install pin): no Pinocchio column")
    print(f"{b} Panda states; times in µs for the whole batch")
    print(f"{'function':<18} {'compiled batch':>15} {'Rust ns × B':>12} {'ratio':>6} {'Pinocchio loop':>15} {'speed-up':>9}")
    for name in FUNCTIONS:
        batch = best(calls[name]) * 1e6
        rust = reference.get(name, float("nan")) * b / 1e3
        loop = best(pinocchio[name], 5) * 1e6 if name in pinocchio else float("nan")
        print(f"{name:<18} {batch:>15.1f} {rust:>12.1f} {batch / rust:>6.2f} {loop:>15.1f} {loop / batch:>9.1f}")


if __name__ == "__main__":
    main()
