"""The rules written once in plain Python give the same bits compiled (numba) as in Python."""

from hypothesis import given
from hypothesis.strategies import floats
from simple_robot_control.compiled_rules import compiled
from simple_robot_control.pose import wrap_number
from stdr_lite.core.kinematics import wrap
from waypoint_lab.course import goal_error

goal_error_compiled = compiled(goal_error)
COORDINATES = floats(-1e4, 1e4)


@given(floats(-1e6, 1e6))
def test_a_heading_wraps_to_the_same_bits_compiled(angle):
    assert wrap(angle) == wrap_number(angle)


@given(COORDINATES, COORDINATES, COORDINATES, COORDINATES, COORDINATES, COORDINATES)
def test_the_goal_error_is_the_same_compiled(x, y, theta, goal_x, goal_y, goal_theta):
    pose = (x, y, theta, goal_x, goal_y, goal_theta)
    assert goal_error_compiled(*pose) == goal_error(*pose)
