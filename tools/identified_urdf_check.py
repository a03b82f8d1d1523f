#!/usr/bin/env python3
"""Check that a URDF written by `dyngen identify -o robot.urdf` (or `dyngen payload -o …`)
gives Pinocchio the dynamics dyngen gives it.

A developer tool, not run by CI. For each URDF it compares, at random states, Pinocchio 4.1's
`rnea` (inverse dynamics) and `crba` (mass matrix) with dyngen's generic dynamics of the same
file, dumped by `cargo run -p dyngen-model --example dynamics_at_states`:

- the URDF alone: the rigid robot with the identified inertials, as both libraries read it
  (dyngen uses `<dynamics>` only when a description chooses the friction columns);
- the identified robot, when the YAML wrapper `robot.dyngen.yaml` is beside it: dyngen loads
  the wrapper (its joint-parameter columns, armature, offsets and Coulomb smoothing, which URDF
  cannot say), Pinocchio the URDF with `model.armature` set from dyngen's armature (Pinocchio
  4.1's `rnea` and `crba` include it), and the joint terms Pinocchio's `rnea` leaves out added
  as docs/identification.md describes them: viscous `damping · q̇`, Coulomb
  `friction · tanh(q̇/ε)` (`sign(q̇)` without smoothing) and the offset. The viscous and
  Coulomb values are Pinocchio's own, read from the URDF's `<dynamics damping friction>`; the
  script first checks they are the values dyngen has.

Joints are matched by name. Positions are uniform within the joint limits, velocities and
accelerations uniform in [-2, 2]. It prints, per file, the largest difference of τ (N·m) and
of D (kg·m²), each also relative to the largest |τ| or |D| entry, and exits with status 1
when one is above --tolerance (relative, default 1e-9).

Set-up (once):

    python3 -m venv /tmp/fxenv
    /tmp/fxenv/bin/pip install -r tools/requirements.txt

Usage (from the repository root):

    dyngen identify robots/arm7_friction.yaml data.csv -o /tmp/id/arm7.urdf
    /tmp/fxenv/bin/python tools/identified_urdf_check.py /tmp/id/arm7.urdf [more.urdf …]
        [--states 100] [--seed 1] [--tolerance 1e-9]
"""

import argparse
import os
import subprocess
import sys

import numpy as np
import pinocchio as pin

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def dyngen_dynamics(description, states):
    """dyngen's joint names, joint terms and (τ, D) per state for `description`."""
    text = "\n".join(" ".join(repr(float(x)) for x in s) for s in states) + "\n"
    run = subprocess.run(
        ["cargo", "run", "--quiet", "-p", "dyngen-model", "--example", "dynamics_at_states", "--", description],
        input=text,
        capture_output=True,
        text=True,
        cwd=REPO,
    )
    if run.returncode != 0:
        sys.exit(f"error: dyngen could not evaluate {description}: {run.stderr.strip()}")
    out = {"terms": {}, "tau": [], "mass": []}
    for line in run.stdout.splitlines():
        head, *rest = line.split()
        if head == "joints":
            out["joints"] = rest
        elif head == "columns":
            out["columns"] = set(rest)
        elif head == "smoothing":
            out["smoothing"] = None if rest[0] == "none" else float(rest[0])
        elif head == "terms":
            out["terms"][rest[0]] = dict(zip(("armature", "viscous", "coulomb", "offset"), map(float, rest[1:])))
        elif head == "tau":
            out["tau"].append(np.array([float(x) for x in rest]))
        elif head == "mass":
            n = int(round(len(rest) ** 0.5))
            out["mass"].append(np.array([float(x) for x in rest]).reshape(n, n))
    return out


def random_states(model, count, rng):
    """`count` states (q, q̇, q̈) in Pinocchio's joint order, q within the limits."""
    low = np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -np.pi)
    high = np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, np.pi)
    return [
        (rng.uniform(low, high), rng.uniform(-2.0, 2.0, model.nv), rng.uniform(-2.0, 2.0, model.nv))
        for _ in range(count)
    ]


def compare(label, model, states, order, dyngen, terms=None):
    """The largest differences of τ and D between Pinocchio (`model`, with `terms` added) and
    `dyngen`, at `states` in Pinocchio's order; `order[i]` is Pinocchio's index of dyngen's
    joint `i`."""
    data = model.createData()
    worst_tau = worst_mass = largest_tau = largest_mass = 0.0
    for (q, v, a), tau_d, mass_d in zip(states, dyngen["tau"], dyngen["mass"]):
        tau_p = pin.rnea(model, data, q, v, a).copy()
        if terms is not None:
            tau_p += terms(v)
        mass_p = pin.crba(model, data, q).copy()
        mass_p = np.triu(mass_p) + np.triu(mass_p, 1).T
        tau_p, mass_p = tau_p[order], mass_p[np.ix_(order, order)]
        worst_tau = max(worst_tau, np.abs(tau_p - tau_d).max())
        worst_mass = max(worst_mass, np.abs(mass_p - mass_d).max())
        largest_tau = max(largest_tau, np.abs(tau_p).max())
        largest_mass = max(largest_mass, np.abs(mass_p).max())
    relative = (worst_tau / largest_tau, worst_mass / largest_mass)
    print(
        f"  {label}: τ differs by at most {worst_tau:.2e} N·m ({relative[0]:.1e} of the largest |τ|, "
        f"{largest_tau:.1f}), D by {worst_mass:.2e} kg·m² ({relative[1]:.1e} of {largest_mass:.2f})"
    )
    return max(relative)


def check(urdf, count, rng):
    """The largest relative difference of the file's checks."""
    model = pin.buildModelFromUrdf(urdf)
    names = list(model.names)[1:]
    states = random_states(model, count, rng)
    print(f"{urdf}: {len(names)} joints, {count} states")
    bare = dyngen_dynamics(urdf, [np.concatenate(s) for s in states])
    missing = set(bare["joints"]) ^ set(names)
    if missing:
        sys.exit(f"error: {urdf}: the joints differ between dyngen and Pinocchio: {sorted(missing)}")
    # dyngen's order, as Pinocchio's indices; the states handed to dyngen in its own order.
    order = [names.index(j) for j in bare["joints"]]
    in_dyngen_order = [np.concatenate([x[order] for x in s]) for s in states]
    bare = dyngen_dynamics(urdf, in_dyngen_order)
    worst = compare("URDF alone (rigid)", model, states, order, bare)

    wrapper = os.path.splitext(urdf)[0] + ".dyngen.yaml"
    if not os.path.exists(wrapper):
        print("  no wrapper beside it: the URDF is the whole identified robot")
        return worst
    full = dyngen_dynamics(wrapper, in_dyngen_order)
    columns, smoothing = full["columns"], full["smoothing"]
    pin_index = {j: names.index(j) for j in full["joints"]}
    for j, t in full["terms"].items():
        for kind, pin_value in (("viscous", model.damping), ("coulomb", model.friction)):
            if kind in columns and not np.isclose(pin_value[pin_index[j]], t[kind], rtol=1e-12, atol=0.0):
                sys.exit(
                    f"error: {urdf}: joint '{j}': the URDF's <dynamics> gives Pinocchio {kind} "
                    f"{pin_value[pin_index[j]]!r}, dyngen's wrapper {t[kind]!r}"
                )
    armature = np.zeros(model.nv)
    offset = np.zeros(model.nv)
    for j, t in full["terms"].items():
        armature[pin_index[j]] = t["armature"]
        offset[pin_index[j]] = t["offset"]
    with_terms = model.copy()
    with_terms.armature[:] = armature
    viscous = model.damping if "viscous" in columns else np.zeros(model.nv)
    coulomb = model.friction if "coulomb" in columns else np.zeros(model.nv)

    def joint_terms(v):
        switch = np.tanh(v / smoothing) if smoothing else np.sign(v)
        return viscous * v + coulomb * switch + offset

    label = f"with the wrapper (columns {', '.join(sorted(columns)) or 'none'}, smoothing {smoothing})"
    return max(worst, compare(label, with_terms, states, order, full, joint_terms))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("urdf", nargs="+")
    parser.add_argument("--states", type=int, default=100)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-9)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    worst = max(check(os.path.abspath(u), args.states, rng) for u in args.urdf)
    print(f"largest relative difference: {worst:.1e} (tolerance {args.tolerance:.0e})")
    return 0 if worst <= args.tolerance else 1


if __name__ == "__main__":
    sys.exit(main())
