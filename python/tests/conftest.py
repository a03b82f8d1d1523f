"""What the tests share: the repository's files, Pinocchio's reference values
(codegen/tests/fixtures, the files the Rust tests read), the tolerance, the robots."""

import json
from pathlib import Path

import numpy as np
import pytest

import dyngen

#: The repository this package is built from.
REPO = Path(__file__).resolve().parents[2]
FIXTURES = REPO / "codegen" / "tests" / "fixtures"
#: Pinocchio's values hold to this relative error (the Rust tests' tolerance).
TOL = 1e-9


def fixture(name):
    """A Pinocchio fixture file, e.g. "panda", "frames/ur5", "floating/solo12"."""
    return json.loads((FIXTURES / f"{name}.json").read_text())


def relative_error(actual, expected):
    """Largest entry-wise difference relative to the largest entry of `expected` (at least 1),
    as tests/testkit's `relative_error`."""
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"shape {actual.shape}, expected {expected.shape}"
    return np.abs(actual - expected).max() / max(np.abs(expected).max(), 1.0)


def assert_close(what, actual, expected, tol=TOL):
    error = relative_error(actual, expected)
    assert error <= tol, f"{what}: relative error {error:.3e} > {tol:.0e}"


def stacked(states, key):
    """Field `key` of every fixture state, as one batch-first array."""
    return np.array([s[key] for s in states], dtype=float)


#: The committed descriptions of the fixtures' robots (the same model Pinocchio built).
DESCRIPTIONS = {"panda": REPO / "robots" / "panda.yaml", "ur5": REPO / "robots" / "ur5.yaml"}


@pytest.fixture(scope="session")
def robots():
    return {name: dyngen.Robot.load(path) for name, path in DESCRIPTIONS.items()}


def fixture_batches(name):
    states = fixture(name)["states"]
    return states, {key: stacked(states, key) for key in ["q", "v", "a", "vr", "ar", "tau"]}


def check_parameters(robot, name):
    assert_close("θ", robot.parameters, fixture(name)["pi"])
    assert robot.joint_names == fixture(name)["joint_names"]


def check_every_quantity(robot, name):
    """Every quantity of `robot` on the batch of the fixture's states, against Pinocchio."""
    states, x = fixture_batches(name)
    q, v, a, vr, ar, tau = (x[k] for k in ["q", "v", "a", "vr", "ar", "tau"])
    rotation, translation = robot.end_effector_pose(q)
    dq, dv = robot.inverse_dynamics_derivatives(q, v, a)
    fq, fv = robot.forward_dynamics_derivatives(q, v, tau)
    results = {
        "ee_rotation": rotation,
        "ee_translation": translation,
        "J": robot.jacobian(q),
        "Jdot": robot.jacobian_dot(q, v),
        "D": robot.mass_matrix(q),
        "C": robot.coriolis_matrix(q, v),
        "g": robot.gravity(q),
        "tau": robot.inverse_dynamics(q, v, a),
        "tau_ref": robot.slotine_li(q, v, vr, ar),
        "Y": robot.regressor(q, v, v, a),
        "aba": robot.forward_dynamics(q, v, tau),
        "Minv": robot.mass_matrix_inverse(q),
        "dtau_dq": dq,
        "dtau_dv": dv,
        "dqdd_dq": fq,
        "dqdd_dv": fv,
    }
    for key, value in results.items():
        assert value.shape[0] == len(states)
        for k, s in enumerate(states):
            assert_close(f"{name} state {k}: {key}", value[k], s[key])
    assert_close("torque regressor", robot.torque_regressor(q, v, a), results["Y"])


def check_base_regressors(robot, name):
    """`Y_b θ_b` against Pinocchio's Slotine–Li torque and inverse dynamics."""
    states, x = fixture_batches(name)
    theta_b = np.array(robot.base_parameters())
    assert len(theta_b) == len(robot.base_parameter_names) < len(robot.parameters)
    yb = robot.base_regressor(x["q"], x["v"], x["vr"], x["ar"])
    assert yb.shape == (len(states), robot.nv, len(theta_b))
    assert_close("Y_b θ_b", yb @ theta_b, stacked(states, "tau_ref"))
    ybt = robot.base_torque_regressor(x["q"], x["v"], x["a"])
    assert_close("Y_b(q, q̇, q̇, q̈) θ_b", ybt @ theta_b, stacked(states, "tau"))


def check_frames(robot, name):
    """Every frame Pinocchio has values for, in the three reference frames."""
    reference = fixture(f"frames/{name}")
    frames = [f["name"] for f in reference["frames"] if f["name"] in robot.frame_names]
    assert len(frames) >= 8, f"{name}: only {frames} are frames of the loaded robot"
    states = reference["states"]
    q, v, a = (stacked(states, k) for k in ["q", "v", "a"])
    for frame in frames:
        rotation, translation = robot.frame_pose(frame, q)
        for k, s in enumerate(states):
            expected = s["frames"][frame]
            assert_close(f"{frame} rotation", rotation[k], expected["rotation"])
            assert_close(f"{frame} translation", translation[k], expected["translation"])
        for ref in ["local", "world", "local_world_aligned"]:
            results = {
                "J": robot.frame_jacobian(frame, q, ref),
                "dJ": robot.frame_jacobian_time_variation(frame, q, v, ref),
                "velocity": robot.frame_velocity(frame, q, v, ref),
                "classical_acceleration": robot.frame_classical_acceleration(frame, q, v, a, ref),
            }
            for key, value in results.items():
                for k, s in enumerate(states):
                    assert_close(f"{frame} {key} {ref} state {k}", value[k], s["frames"][frame][key][ref])


def check_against_pinocchio(robot, name):
    """Everything Pinocchio has values for: θ and the joints, every quantity, the base
    regressors, the frames."""
    check_parameters(robot, name)
    check_every_quantity(robot, name)
    check_base_regressors(robot, name)
    check_frames(robot, name)


#: The batch methods of the fixed-base dynamics and the fixture arrays they take.
METHODS = [
    ("end_effector_pose", ["q"]),
    ("jacobian", ["q"]),
    ("jacobian_dot", ["q", "v"]),
    ("mass_matrix", ["q"]),
    ("coriolis_matrix", ["q", "v"]),
    ("gravity", ["q"]),
    ("inverse_dynamics", ["q", "v", "a"]),
    ("slotine_li", ["q", "v", "vr", "ar"]),
    ("regressor", ["q", "v", "vr", "ar"]),
    ("torque_regressor", ["q", "v", "a"]),
    ("base_regressor", ["q", "v", "vr", "ar"]),
    ("base_torque_regressor", ["q", "v", "a"]),
    ("forward_dynamics", ["q", "v", "tau"]),
    ("mass_matrix_inverse", ["q"]),
    ("inverse_dynamics_derivatives", ["q", "v", "a"]),
    ("forward_dynamics_derivatives", ["q", "v", "tau"]),
    ("energy_regressor", ["q", "v"]),
]


def call(robot, method, arguments, batches, state=None):
    """`method` of `robot` on the named fixture batches (or on their row `state` alone),
    its results as a tuple."""
    arrays = (batches[k] if state is None else batches[k][state] for k in arguments)
    result = getattr(robot, method)(*arrays)
    return result if isinstance(result, tuple) else (result,)


def check_single_states_are_batch_rows(robot, method, arguments, batches, states, tol):
    """`method` on each of `states` alone gives that state's row of the batch's results, to
    `tol` (0: bit for bit)."""
    batch = call(robot, method, arguments, batches)
    for k in states:
        for single, rows in zip(call(robot, method, arguments, batches, k), batch):
            assert single.shape == rows.shape[1:]
            assert_close(f"{method} state {k}", single, rows[k], tol)
    return batch
