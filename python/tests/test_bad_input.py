"""Bad input raises one clear error, naming the argument, the state or the place; it never
crashes the interpreter nor computes a wrong result."""

import numpy as np
import pytest

import dyngen
from conftest import REPO

BAD = REPO / "codegen" / "tests" / "data" / "bad"


def test_a_bad_description_is_a_description_error_with_its_place():
    with pytest.raises(dyngen.DescriptionError) as caught:
        dyngen.Robot.load(BAD / "zero-axis.yaml")
    error = caught.value
    assert (error.line, error.column) == (24, 11)
    assert error.file.endswith("zero-axis.yaml")
    assert error.item == "joint 'elbow'"
    assert error.problem == "axis [0, 0, 0] has zero length"
    assert str(error) == f"{error.file}:24:11: joint 'elbow': axis [0, 0, 0] has zero length"
    assert isinstance(error, dyngen.DyngenError)


def test_loading_options_reach_the_loader():
    urdf = REPO / "robots" / "urdf" / "panda.urdf"
    with pytest.raises(dyngen.DescriptionError, match="locked joint 'nope'"):
        dyngen.Robot.load(urdf, locked_joints={"nope": 0.0})
    with pytest.raises(dyngen.DescriptionError, match="end-effector 'nowhere'"):
        dyngen.Robot.load(urdf, end_effector="nowhere")
    with pytest.raises(dyngen.DescriptionError, match="unknown file type"):
        dyngen.Robot.load(REPO / "README.md")
    with pytest.raises(dyngen.DescriptionError, match="`gravity` was chosen twice"):
        dyngen.Robot.load(REPO / "robots" / "panda.yaml", gravity=(0, 0, -1.62))
    with pytest.raises(ValueError, match="inertia: expected"):
        dyngen.Robot.load(urdf, inertia="sloppy")
    with pytest.raises(ValueError, match="gravity: expected three finite numbers"):
        dyngen.Robot.load(urdf, gravity=(0, float("nan"), 1))
    moon = dyngen.Robot.load(
        urdf,
        locked_joints={"panda_finger_joint1": 0.0, "panda_finger_joint2": 0.0},
        end_effector="panda_hand_tcp",
        frames=["panda_link4", "panda_hand"],
        gravity=(0, 0, -1.62),
    )
    assert moon.dof == 7 and moon.frame_names == ["panda_hand_tcp", "panda_link4", "panda_hand"]
    assert moon.gravity_vector == [0.0, 0.0, -1.62]
    earth = dyngen.Robot.load(REPO / "robots" / "panda.yaml")
    q = np.linspace(-0.5, 0.5, 7)
    np.testing.assert_allclose(moon.gravity(q), earth.gravity(q) * 1.62 / 9.81, rtol=1e-12, atol=1e-12)


def test_wrong_shapes_are_refused_naming_the_argument(robots):
    robot = robots["ur5"]
    with pytest.raises(ValueError, match=r"argument 'q': shape \[7\], expected \(6,\)"):
        robot.mass_matrix(np.zeros(7))
    with pytest.raises(ValueError, match=r"argument 'qd': shape \[2, 5\]"):
        robot.coriolis_matrix(np.zeros((2, 6)), np.zeros((2, 5)))
    with pytest.raises(ValueError, match="argument 'qdd': a batch of 3 but 'q' is a batch of 2"):
        robot.inverse_dynamics(np.zeros((2, 6)), np.zeros((2, 6)), np.zeros((3, 6)))
    with pytest.raises(ValueError, match="argument 'qd': one state but 'q' is a batch of 2"):
        robot.coriolis_matrix(np.zeros((2, 6)), np.zeros(6))
    with pytest.raises(ValueError, match=r"shape \[1, 2, 6\]"):
        robot.gravity(np.zeros((1, 2, 6)))
    with pytest.raises(ValueError, match="argument 'q': not an array of numbers"):
        robot.gravity(["a"] * 6)


def test_non_finite_entries_are_refused_naming_state_and_entry(robots):
    robot = robots["ur5"]
    q = np.zeros((4, 6))
    q[2, 3] = np.nan
    with pytest.raises(ValueError, match="argument 'q': state 2, entry 3 is NaN"):
        robot.mass_matrix(q)
    with pytest.raises(ValueError, match="argument 'tau': entry 0 is inf"):
        robot.forward_dynamics(np.zeros(6), np.zeros(6), [np.inf, 0, 0, 0, 0, 0])


def test_unknown_frames_and_reference_frames_list_the_choices(robots):
    robot = robots["ur5"]
    with pytest.raises(ValueError, match="unknown frame 'gripper': the robot's frames are tool0"):
        robot.frame_pose("gripper", np.zeros(6))
    with pytest.raises(ValueError, match="unknown reference frame 'global'"):
        robot.frame_jacobian("tool0", np.zeros(6), "global")


def test_wrong_parameters_are_refused(robots):
    robot = robots["ur5"]
    with pytest.raises(ValueError, match="theta has 3 entries, but the robot has 60 parameters"):
        robot.with_parameters([1.0, 2.0, 3.0])
    theta = robot.parameters
    theta[5] = np.nan
    with pytest.raises(ValueError, match=r"theta\[5\] \(Ixy\[shoulder_link\]\) is NaN"):
        robot.base_parameters(theta)
