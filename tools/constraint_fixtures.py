#!/usr/bin/env python3
"""Regenerate the constrained-dynamics Pinocchio reference fixtures of
codegen/tests/fixtures/constrained/.

A developer tool, not run by CI. For the floating-base robots of tools/floating_fixtures.py it
holds frames to the world with Pinocchio's rigid constraints (`pin.RigidConstraintModel`, the
second joint the universe) and writes, for seeded random states: constrained forward dynamics
(`pin.constraintDynamics`) with and without Baumgarte stabilisation, exact (mu = 0) and
proximal (mu > 0, iterated until converged); impulse dynamics (`pin.impulseDynamics`), exact
and damped; the constraint Jacobian, the mass matrix and the operational-space inertia
`(J M⁻¹ Jᵀ)⁻¹` computed from them; and the derivatives of constrained forward dynamics
(`pin.computeConstraintDynamicsDerivatives`). Before writing, it checks each state against
the equations the solution must satisfy and stops at the first failure.

Set-up and usage as tools/floating_fixtures.py:

    /tmp/fxenv/bin/python tools/constraint_fixtures.py            # every robot
    /tmp/fxenv/bin/python tools/constraint_fixtures.py solo12 --out /tmp/fx

Run twice, it writes byte-identical files.
"""

import argparse
import os
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from floating_fixtures import ROBOTS, build_model, describe_model, draw_states, relative, Worst
from pinocchio_reference import pose, seed_of, symmetric_from_upper, to_json

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
LOCAL = pin.ReferenceFrame.LOCAL
REFERENCE_NAMES = {LOCAL: "local", LWA: "local_world_aligned"}

KP = 10.0  # Baumgarte gains of the stabilised solve (every axis)
KD = 2.0 * np.sqrt(KP)
ANCHOR_OFFSET = 0.02  # m and rad: how far each anchor is from where its frame is
PROXIMAL_MU = 1e-4
PROXIMAL_ACCURACY = 1e-14
PROXIMAL_MAX_ITER = 200
DAMPED_MU = 1e-3
RESTITUTION = 0.3
TORQUE_RANGE = 5.0


@dataclass(frozen=True)
class ConstraintSet:
    robot: str
    # (frame name, "point" | "frame", reference frame), in the order of the constraint rows
    contacts: tuple
    states: int


SETS = {
    s.robot: s
    for s in [
        ConstraintSet(
            "solo12",
            (
                ("FL_FOOT", "point", LOCAL),
                ("FR_FOOT", "point", LWA),
                ("HL_FOOT", "point", LOCAL),
                ("HR_FOOT", "point", LWA),
            ),
            8,
        ),
        ConstraintSet(
            "g1",
            (
                ("left_ankle_roll_link", "frame", LOCAL),
                ("right_ankle_roll_link", "frame", LWA),
            ),
            4,
        ),
    ]
}


def constraint_models(model, data, q, constraint_set, frame_ids, rng, gains):
    """Pinocchio's constraints holding each frame to an anchor near where the frame is at q."""
    pin.framesForwardKinematics(model, data, q)
    models, anchors = [], []
    for (name, kind, reference), f in zip(constraint_set.contacts, frame_ids):
        frame = model.frames[f]
        offset = pin.exp6(pin.Motion(rng.uniform(-ANCHOR_OFFSET, ANCHOR_OFFSET, 6)))
        anchor = data.oMf[f] * offset
        contact_type = pin.ContactType.CONTACT_3D if kind == "point" else pin.ContactType.CONTACT_6D
        cm = pin.RigidConstraintModel(contact_type, model, frame.parentJoint, frame.placement, 0, anchor, reference)
        cm.name = name
        if gains:
            corrector = cm.m_baumgarte_parameters
            corrector.Kp, corrector.Kd = KP, KD
            cm.setBaumgarteCorrectorParameters(corrector)
        models.append(cm)
        anchors.append(anchor)
    return models, anchors


def constraint_jacobian(model, data, q, cms):
    datas = pin.StdVec_RigidConstraintData([cm.createData() for cm in cms])
    pin.computeJointJacobians(model, data, q)
    pin.framesForwardKinematics(model, data, q)
    for cm, cdata in zip(cms, datas):
        cm.calc(model, data, cdata)
    return pin.getConstraintsJacobian(model, data, pin.StdVec_RigidConstraintModel(cms), datas).copy()


def solve(model, q, v, tau, cms, mu, max_iter, accuracy):
    data = model.createData()
    datas = pin.StdVec_RigidConstraintData([cm.createData() for cm in cms])
    cms = pin.StdVec_RigidConstraintModel(cms)
    pin.initConstraintDynamics(model, data, cms, datas)
    settings = pin.ProximalSettings(accuracy, mu, max_iter)
    ddq = pin.constraintDynamics(model, data, q, v, tau, cms, datas, settings).copy()
    return data, datas, settings, ddq, data.lambda_c.copy()


def impulse(model, q, v, cms, mu):
    data = model.createData()
    datas = pin.StdVec_RigidConstraintData([cm.createData() for cm in cms])
    cms = pin.StdVec_RigidConstraintModel(cms)
    pin.initConstraintDynamics(model, data, cms, datas)
    settings = pin.ProximalSettings(1e-12, mu, 1)
    v_after = pin.impulseDynamics(model, data, q, v, cms, datas, RESTITUTION, settings).copy()
    return v_after, data.impulse_c.copy()


class Checks(Worst):
    """`Worst`, and residuals only reported."""

    def note(self, name, residual):
        self.values[name] = max(self.values.get(name, 0.0), residual)


def check_derivatives(model, q, v, tau, cms, sdata, worst, h=1e-6):
    """Pinocchio's derivatives of (a, λ) against central differences along each direction of
    q (on the configuration manifold), v and τ."""
    nv = model.nv

    def at(q_, v_, tau_):
        _, _, _, ddq, lam = solve(model, q_, v_, tau_, cms, 0.0, 1, 1e-12)
        return np.concatenate([ddq, lam])

    for name, ours, step in (
        ("q", (sdata.ddq_dq, sdata.dlambda_dq), lambda e: (pin.integrate(model, q, e), v, tau)),
        ("v", (sdata.ddq_dv, sdata.dlambda_dv), lambda e: (q, v + e, tau)),
        ("tau", (sdata.ddq_dtau, sdata.dlambda_dtau), lambda e: (q, v, tau + e)),
    ):
        fd = np.column_stack(
            [(at(*step(h * np.eye(nv)[j])) - at(*step(-h * np.eye(nv)[j]))) / (2 * h) for j in range(nv)]
        )
        expected = np.vstack(ours)
        stabilised = cms[0].m_baumgarte_parameters.Kp != 0
        frame_contacts = any(cm.type == pin.ContactType.CONTACT_6D for cm in cms)
        if stabilised and frame_contacts and name == "q":
            # Pinocchio leaves the derivative of log6 out of the Baumgarte term's derivative
            # (its code says so: `Kp /* * Jexp6 */`), so with 6-D contacts and gains its ∂/∂q
            # is an approximation; reported, not held.
            worst.note(f"d(a, λ)/dq stabilised 6-D (approximate in Pinocchio)", relative(expected - fd, expected))
            continue
        label = "stabilised" if stabilised else "plain"
        worst.check(f"d(a, λ)/d{name} {label} (central differences)", relative(expected - fd, expected), 1e-5)


def evaluate(model, frame_ids, constraint_set, q, v, tau, rng, worst):
    data = model.createData()
    M = symmetric_from_upper(pin.crba(model, data, q))
    nle = pin.nonLinearEffects(model, data, q, v).copy()
    plain, _ = constraint_models(model, data, q, constraint_set, frame_ids, rng, gains=False)
    stabilised, anchors = constraint_models(model, data, q, constraint_set, frame_ids, rng, gains=True)
    J = constraint_jacobian(model, data, q, plain)
    Minv = np.linalg.inv(M)
    delassus = J @ Minv @ J.T
    osim = np.linalg.inv(delassus)

    exact = {}
    for label, cms in (("plain", plain), ("stabilised", stabilised)):
        sdata, sdatas, _, ddq, lam = solve(model, q, v, tau, cms, 0.0, 1, 1e-12)
        # M a = tau - nle + Jᵀ λ, and the constraint rows' acceleration as asked.
        worst.check("M a = tau - nle + Jᵀ λ", relative(M @ ddq - (tau - nle + J.T @ lam), tau - nle), 1e-9)
        _, _, settings, ddq_prox, lam_prox = solve(
            model, q, v, tau, cms, PROXIMAL_MU, PROXIMAL_MAX_ITER, PROXIMAL_ACCURACY
        )
        worst.check("proximal = exact (a)", relative(ddq_prox - ddq, ddq), 1e-9)
        worst.check("proximal = exact (λ)", relative(lam_prox - lam, lam), 1e-9)
        pin.computeConstraintDynamicsDerivatives(model, sdata, cms, sdatas)
        check_derivatives(model, q, v, tau, cms, sdata, worst)
        exact[label] = {
            "ddq": ddq.tolist(),
            "lambda": lam.tolist(),
            "ddq_dq": sdata.ddq_dq.tolist(),
            "ddq_dv": sdata.ddq_dv.tolist(),
            "ddq_dtau": sdata.ddq_dtau.tolist(),
            "dlambda_dq": sdata.dlambda_dq.tolist(),
            "dlambda_dv": sdata.dlambda_dv.tolist(),
            "dlambda_dtau": sdata.dlambda_dtau.tolist(),
            "proximal_iterations": int(settings.iter),
        }
    # Without gains the rows' acceleration is zero: J a + drift = 0, the drift from a solve
    # with a = 0 … checked through a finite difference of J v along the motion.
    h = 1e-6
    q_plus, q_minus = pin.integrate(model, q, h * v), pin.integrate(model, q, -h * v)
    a = np.array(exact["plain"]["ddq"])
    J_plus = constraint_jacobian(model, model.createData(), q_plus, plain)
    J_minus = constraint_jacobian(model, model.createData(), q_minus, plain)
    Jdot_v = (J_plus - J_minus) @ v / (2 * h)
    # For point contacts the rows are the classical acceleration, d/dt (J v) exactly when the
    # frame's rotation does not enter (LWA); checked on those rows only.
    row = 0
    for name, kind, reference in constraint_set.contacts:
        size = 3 if kind == "point" else 6
        if kind == "point" and reference == LWA:
            rows = slice(row, row + size)
            worst.check("J a + J̇ v = 0 (point, LWA)", relative(J[rows] @ a + Jdot_v[rows], J[rows] @ a), 1e-6)
        row += size

    v_after, impulses = impulse(model, q, v, plain, 0.0)
    worst.check("J v⁺ = -r J v⁻", relative(J @ v_after + RESTITUTION * (J @ v), J @ v), 1e-9)
    worst.check("M (v⁺ - v⁻) = Jᵀ Λ", relative(M @ (v_after - v) - J.T @ impulses, J.T @ impulses), 1e-9)
    v_damped, impulses_damped = impulse(model, q, v, plain, DAMPED_MU)

    return {
        "q": q.tolist(),
        "v": v.tolist(),
        "tau": tau.tolist(),
        "anchors": [pose(a) for a in anchors],
        "M": M.tolist(),
        "J": J.tolist(),
        "operational_space_inertia": osim.tolist(),
        "forward": exact,
        "impulse": {"v_after": v_after.tolist(), "impulse": impulses.tolist()},
        "impulse_damped": {"v_after": v_damped.tolist(), "impulse": impulses_damped.tolist()},
    }


def fixture(constraint_set, worst):
    robot = ROBOTS[constraint_set.robot]
    model, _ = build_model(robot)
    frame_ids = []
    for name, _, _ in constraint_set.contacts:
        frame_ids.append(model.getFrameId(name, pin.FrameType.BODY))
    rng = np.random.default_rng(seed_of(constraint_set.robot + "/constrained"))
    states = draw_states(model, robot.name + "/constrained", constraint_set.states)
    evaluated = []
    for q, v, _, _, _ in states:
        tau = rng.uniform(-TORQUE_RANGE, TORQUE_RANGE, model.nv)
        evaluated.append(evaluate(model, frame_ids, constraint_set, q, v, tau, rng, worst))
    described = describe_model(model, [], robot)
    described.pop("frames")
    return {
        **described,
        "contacts": [
            {
                "frame": name,
                "kind": kind,
                "reference": REFERENCE_NAMES[reference],
                "parent_joint": model.names[model.frames[f].parentJoint],
                "placement": pose(model.frames[f].placement),
            }
            for (name, kind, reference), f in zip(constraint_set.contacts, frame_ids)
        ],
        "baumgarte": {"kp": KP, "kd": KD},
        "proximal": {"mu": PROXIMAL_MU, "accuracy": PROXIMAL_ACCURACY, "max_iter": PROXIMAL_MAX_ITER},
        "damped_mu": DAMPED_MU,
        "restitution": RESTITUTION,
        "states": evaluated,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", help=f"any of {', '.join(SETS)} (default: all)")
    parser.add_argument("--out", default=os.path.join(REPO, "codegen", "tests", "fixtures", "constrained"))
    args = parser.parse_args()
    unknown = [r for r in args.robots if r not in SETS]
    if unknown:
        parser.error(f"unknown robot(s) {', '.join(unknown)}; known: {', '.join(SETS)}")
    for name in args.robots or list(SETS):
        worst = Checks()
        result = fixture(SETS[name], worst)
        write(args.out, name, result, f"nv {result['nv']}, {len(result['states'])} states", worst)


def write(directory, name, result, summary, worst):
    """`result` as `directory/name.json`, and what was checked on the way."""
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, name + ".json")
    with open(path, "w") as f:
        f.write(to_json(result) + "\n")
    print(f"{path}: {summary}")
    for check, value in worst.values.items():
        print(f"  {check:48} worst {value:.1e}")


if __name__ == "__main__":
    main()
