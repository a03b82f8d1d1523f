"""The generic dynamics (dyngen.Robot) against Pinocchio's values, on batches and on single
states; a batch's row equals the single state's result."""

import numpy as np
import pytest

from conftest import assert_close, fixture, stacked

ROBOTS = ["panda", "ur5"]


def fixture_batches(name):
    states = fixture(name)["states"]
    return states, {key: stacked(states, key) for key in ["q", "v", "a", "vr", "ar", "tau"]}


@pytest.mark.parametrize("name", ROBOTS)
def test_parameters_are_pinocchios(robots, name):
    robot = robots[name]
    assert_close("θ", robot.parameters, fixture(name)["pi"])
    assert robot.joint_names == fixture(name)["joint_names"]


@pytest.mark.parametrize("name", ROBOTS)
def test_every_quantity_of_a_batch_matches_pinocchio(robots, name):
    robot = robots[name]
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


@pytest.mark.parametrize("name", ROBOTS)
def test_base_regressors_times_base_parameters_give_the_torques(robots, name):
    robot = robots[name]
    states, x = fixture_batches(name)
    theta_b = np.array(robot.base_parameters())
    assert len(theta_b) == len(robot.base_parameter_names) < len(robot.parameters)
    yb = robot.base_regressor(x["q"], x["v"], x["vr"], x["ar"])
    assert yb.shape == (len(states), robot.nv, len(theta_b))
    assert_close("Y_b θ_b", yb @ theta_b, stacked(states, "tau_ref"))
    ybt = robot.base_torque_regressor(x["q"], x["v"], x["a"])
    assert_close("Y_b(q, q̇, q̇, q̈) θ_b", ybt @ theta_b, stacked(states, "tau"))


@pytest.mark.parametrize("name", ROBOTS)
def test_frames_match_pinocchio_in_every_reference_frame(robots, name):
    robot = robots[name]
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


def as_tuple(result):
    return result if isinstance(result, tuple) else (result,)


@pytest.mark.parametrize("method,arguments", METHODS)
def test_a_single_state_equals_its_row_of_the_batch(robots, method, arguments):
    robot = robots["panda"]
    _, x = fixture_batches("panda")
    batch = as_tuple(getattr(robot, method)(*(x[k] for k in arguments)))
    for k in [0, 7, 19]:
        single = as_tuple(getattr(robot, method)(*(x[name][k] for name in arguments)))
        for b, s in zip(batch, single):
            assert s.shape == b.shape[1:]
            np.testing.assert_array_equal(s, b[k])


def test_non_contiguous_and_list_inputs_give_the_same_values(robots):
    robot = robots["panda"]
    _, x = fixture_batches("panda")
    q, v, a = x["q"], x["v"], x["a"]
    expected = robot.inverse_dynamics(q, v, a)
    fortran = np.asfortranarray(q)
    strided = np.repeat(q, 2, axis=0)[::2]
    assert not strided.flags.c_contiguous and not fortran.flags.c_contiguous
    np.testing.assert_array_equal(robot.inverse_dynamics(fortran, v, a), expected)
    np.testing.assert_array_equal(robot.inverse_dynamics(strided, v, a), expected)
    np.testing.assert_array_equal(robot.inverse_dynamics(q[3].tolist(), list(v[3]), a[3]), expected[3])
    columns = np.ascontiguousarray(q.T).T
    np.testing.assert_array_equal(robot.mass_matrix(columns), robot.mass_matrix(q))


def test_an_empty_batch_gives_empty_results(robots):
    robot = robots["ur5"]
    assert robot.mass_matrix(np.zeros((0, 6))).shape == (0, 6, 6)


def test_with_parameters_scales_the_dynamics(robots):
    robot = robots["ur5"]
    _, x = fixture_batches("ur5")
    doubled = robot.with_parameters([2 * p for p in robot.parameters])
    tau = robot.inverse_dynamics(x["q"], x["v"], x["a"])
    assert_close("2θ", doubled.inverse_dynamics(x["q"], x["v"], x["a"]), 2 * tau)
    y = robot.regressor(x["q"], x["v"], x["v"], x["a"])
    assert_close("Y θ", y @ np.array(robot.parameters), tau)
