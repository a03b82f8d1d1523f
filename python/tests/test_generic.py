"""The generic dynamics (dyngen.Robot) against Pinocchio's values, on batches and on single
states; a batch's row equals the single state's result."""

import numpy as np
import pytest

from conftest import METHODS, assert_close, check_against_pinocchio, check_single_states_are_batch_rows, fixture_batches


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_parameters_every_quantity_base_regressors_and_frames_match_pinocchio(robots, name):
    check_against_pinocchio(robots[name], name)


@pytest.mark.parametrize("method,arguments", METHODS)
def test_a_single_state_equals_its_row_of_the_batch(robots, method, arguments):
    _, x = fixture_batches("panda")
    check_single_states_are_batch_rows(robots["panda"], method, arguments, x, [0, 7, 19], tol=0)


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
