"""The compiled robot (dyngen.compile: the generated code as its C library) against Pinocchio's
values, the generic dynamics and itself; its cache; bad input. One robot, the UR5 with every
group of functions, built unoptimised (the values do not depend on the optimisation)."""

import os
import time

import numpy as np
import pytest

import dyngen
from conftest import (
    DESCRIPTIONS,
    METHODS,
    assert_close,
    call,
    check_against_pinocchio,
    check_single_states_are_batch_rows,
    fixture_batches,
)

OPTIONS = dict(functions="all", opt_level=0)


@pytest.fixture(scope="module")
def compiled():
    return dyngen.compile(DESCRIPTIONS["ur5"], **OPTIONS)


def test_every_quantity_matches_pinocchio(compiled):
    check_against_pinocchio(compiled, "ur5")


@pytest.mark.parametrize("method,arguments", METHODS[:-1])
def test_every_method_equals_the_generic_one_and_a_state_its_row(compiled, robots, method, arguments):
    _, x = fixture_batches("ur5")
    # A batch may run four states at once in SIMD lanes (the base torque regressor): the
    # same values to rounding (docs/c-library.md).
    generated = check_single_states_are_batch_rows(compiled, method, arguments, x, [0, 11, 19], tol=1e-14)
    for g, r in zip(generated, call(robots["ur5"], method, arguments, x)):
        assert_close(method, g, r, 1e-10)


def test_names_sizes_and_base_parameters_are_the_descriptions(compiled, robots):
    robot = robots["ur5"]
    assert (compiled.dof, compiled.nq, compiled.nv) == (6, 6, 6)
    assert compiled.joint_names == robot.joint_names
    assert compiled.frame_names == robot.frame_names
    assert compiled.base_parameter_names == robot.base_parameter_names
    assert_close("θ_b", compiled.base_parameters(), robot.base_parameters(), 1e-12)


def test_a_second_compile_is_the_cached_library(compiled):
    before = os.stat(compiled.path).st_mtime_ns
    start = time.perf_counter()
    again = dyngen.compile(DESCRIPTIONS["ur5"], **OPTIONS)
    assert time.perf_counter() - start < 5.0
    assert again.path == compiled.path and os.stat(again.path).st_mtime_ns == before


def test_bad_input_raises(compiled):
    with pytest.raises(ValueError, match=r"argument 'q': shape \[5\]"):
        compiled.mass_matrix(np.zeros(5))
    with pytest.raises(ValueError, match="argument 'qd': state 1, entry 0 is NaN"):
        compiled.coriolis_matrix(np.zeros((2, 6)), [[0] * 6, [np.nan] + [0] * 5])
    with pytest.raises(ValueError, match="unknown frame 'gripper'"):
        compiled.frame_pose("gripper", np.zeros(6))
    with pytest.raises(ValueError, match="unknown reference frame"):
        compiled.frame_velocity("tool0", np.zeros(6), np.zeros(6), "base")
    with pytest.raises(ValueError, match="the compiled robot has no function 'center_of_mass'"):
        compiled.center_of_mass(np.zeros(6))


def test_without_cargo_compile_says_what_it_needs(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("CARGO", raising=False)
    monkeypatch.delenv("CARGO_HOME", raising=False)
    with pytest.raises(dyngen.CompileError, match="needs a Rust toolchain"):
        dyngen.compile(DESCRIPTIONS["ur5"], functions=["regressors"], cache_dir=tmp_path)


def test_a_robot_with_other_parameters_is_not_compiled(robots):
    robot = robots["ur5"]
    with pytest.raises(dyngen.CompileError, match="with_parameters"):
        dyngen.compile(robot.with_parameters(robot.parameters), cache_dir="/nonexistent")
