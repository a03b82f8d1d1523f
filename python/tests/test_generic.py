"""The generic dynamics (dyngen.Robot) against Pinocchio's values, on batches and on single
states; a batch's row equals the single state's result."""

import numpy as np
import pytest

from conftest import (
    assert_close,
    check_base_regressors,
    check_every_quantity,
    check_frames,
    check_parameters,
    fixture_batches,
)

ROBOTS = ["panda", "ur5"]


@pytest.mark.parametrize("name", ROBOTS)
def test_parameters_and_every_quantity_of_a_batch_match_pinocchio(robots, name):
    check_parameters(robots[name], name)
    check_every_quantity(robots[name], name)


@pytest.mark.parametrize("name", ROBOTS)
def test_base_regressors_times_base_parameters_give_the_torques(robots, name):
    check_base_regressors(robots[name], name)


@pytest.mark.parametrize("name", ROBOTS)
def test_frames_match_pinocchio_in_every_reference_frame(robots, name):
    check_frames(robots[name], name)


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
