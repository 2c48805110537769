"""The lab's goal set and the heading rule: one function each, for one pose or many."""

import math

from hypothesis import given
from hypothesis.strategies import floats
import numpy as np
from simple_robot_control.pose import wrap_angle
from waypoint_lab.course import goal_error, goal_errors, in_goal_set
from waypoint_lab.rules import ANGLE_TOLERANCE, DISTANCE_TOLERANCE
from waypoint_lab.waypoints import Waypoint


def test_the_goal_set_is_d_and_t_around_the_waypoint_across_the_wrap():
    assert in_goal_set((DISTANCE_TOLERANCE, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert not in_goal_set((DISTANCE_TOLERANCE + 1e-9, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert in_goal_set((0.0, 0.0, math.pi - 0.01), Waypoint(0.0, 0.0, -math.pi + 0.01))
    assert not in_goal_set((0.0, 0.0, ANGLE_TOLERANCE + 1e-6), (0.0, 0.0, 0.0))
    assert in_goal_set((0.3, 0.0, 0.0), (0.0, 0.0, 0.0), distance_tolerance=0.5)


def test_one_pose_at_a_time_and_rows_of_poses_agree():
    rng = np.random.default_rng(1)
    poses = rng.uniform([-0.2, -0.2, -math.pi], [0.2, 0.2, math.pi], (2000, 3))
    goal = Waypoint(0.0, 0.0, 3.1)
    rows = in_goal_set(poses, np.tile(goal, (len(poses), 1)))
    one_by_one = [bool(in_goal_set(tuple(pose), goal)) for pose in poses]
    assert rows.tolist() == one_by_one and any(one_by_one) and not all(one_by_one)
    distance, heading = goal_errors(poses, goal)
    assert np.all(heading <= math.pi) and np.allclose(distance, np.hypot(*poses[:, :2].T))
    assert [goal_error(*pose, *goal) for pose in poses] == list(zip(distance, heading))


@given(floats(-1e4, 1e4))
def test_wrap_angle_is_one_rule_for_numbers_and_arrays(angle):
    one, many = wrap_angle(angle), wrap_angle(np.array([angle, angle]))
    assert isinstance(one, float) and one == many[0] == many[1]
    assert -math.pi < one <= math.pi
    assert math.isclose(math.cos(one), math.cos(angle), abs_tol=1e-9)
