"""Plans into a goal set: where they end, how long they take, and what walls veto."""

import math

import numpy as np
import pytest
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.kinematics import arc_step
from waypoint_controller.clearance import Clearance
from waypoint_controller.config import ControllerConfig
from waypoint_controller.control_law import plan_limits, PlannedLaw
from waypoint_controller.planner import (fastest_plan, goal_set_poses, Limits,
                                         plan_to_goal_set, ReedsSheppPlan, TurnPlan)
from waypoint_lab.course import in_goal_set
from waypoint_lab.waypoints import Waypoint

CONFIG = ControllerConfig()
LIMITS = plan_limits(CONFIG)


def test_every_end_pose_tried_lies_inside_the_goal_set():
    waypoint = Waypoint(1.0, -2.0, 3.0)
    for pose in goal_set_poses((waypoint.x, waypoint.y, waypoint.theta), LIMITS):
        assert in_goal_set(pose, waypoint)


def test_a_turn_on_the_spot_beats_any_path_when_the_position_is_right():
    plan = fastest_plan((0.0, 0.0, 0.0), (0.0, 0.0, 2.0), LIMITS)
    assert isinstance(plan, TurnPlan)
    assert plan.duration == pytest.approx(2.0 / LIMITS.rate)
    assert plan.pose_at(plan.duration) == pytest.approx((0.0, 0.0, 2.0))


def test_a_turn_may_shift_the_position_on_the_way():
    plan = TurnPlan((0.0, 0.0, 0.0), math.pi, (0.1, 0.05), LIMITS)
    assert plan.feasible
    assert plan.pose_at(plan.duration) == pytest.approx((0.1, 0.05, math.pi))
    too_far = TurnPlan((0.0, 0.0, 0.0), 0.2, (0.5, 0.0), LIMITS)
    assert not too_far.feasible


def test_plans_end_where_they_say_and_take_path_length_over_speed():
    plan = fastest_plan((0.0, 0.0, 0.0), (2.0, 1.0, 1.0), LIMITS)
    assert isinstance(plan, ReedsSheppPlan)
    assert plan.pose_at(plan.duration) == pytest.approx((2.0, 1.0, 1.0), abs=1e-9)
    assert plan.pose_at(10 * plan.duration) == pytest.approx(plan.pose_at(plan.duration))


def test_the_end_pose_is_chosen_for_the_leg_after_too():
    start, waypoint, after = (0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 3.0, math.pi / 2)
    alone = plan_to_goal_set(start, waypoint, LIMITS)
    ahead = plan_to_goal_set(start, waypoint, LIMITS, after)
    assert ahead.pose_at(ahead.duration)[1] > alone.pose_at(alone.duration)[1]


def room_with_a_wall_at_the_left():
    """Return a 4 m x 4 m map at 5 cm whose columns left of x = 0.35 m are wall."""
    cells = np.zeros((80, 80), dtype=np.int8)
    cells[:, :7] = 100
    return Clearance(OccupancyMap(cells, 0.05, (0.0, 0.0, 0.0)), robot_radius=0.2)


def test_clearance_is_measured_to_the_wall_edge():
    clearance = room_with_a_wall_at_the_left()
    assert clearance.at(1.0, 2.0) == pytest.approx(0.65, abs=0.01)
    assert clearance.at(0.1, 2.0) < 0.0
    assert clearance.at(-5.0, 2.0) == math.inf


def test_a_waypoint_beside_a_wall_facing_away_is_reached_without_touching_it():
    clearance = room_with_a_wall_at_the_left()
    waypoint = Waypoint(0.75, 2.5, 0.0)
    free = PlannedLaw([waypoint], CONFIG, is_free=clearance.is_free)
    blind = PlannedLaw([waypoint], CONFIG)
    poses = {}
    for name, law in (('free', free), ('blind', blind)):
        pose, trace = (0.8, 3.0, 1.57), []
        law.aim(pose, 0)
        while not in_goal_set(pose, waypoint) and len(trace) < 1200:
            pose = tuple(float(v) for v in arc_step(*pose, *law.command(pose, 0.05), 0.05))
            trace.append(pose)
        poses[name] = trace
    assert in_goal_set(poses['free'][-1], waypoint)
    assert min(clearance.at(x, y) for x, y, _ in poses['free']) > 0.2 - 0.005
    assert min(clearance.at(x, y) for x, y, _ in poses['blind']) < 0.2


def test_with_every_plan_vetoed_the_robot_stops():
    law = PlannedLaw([Waypoint(2.0, 0.0, 0.0)], CONFIG, is_free=lambda plan: False)
    law.aim((0.0, 0.0, 0.0), 0)
    assert law.command((0.0, 0.0, 0.0), 0.05) == (0.0, 0.0)
    assert law.controller.plan is None


def test_limits_give_the_turning_radius():
    assert Limits(0.5, 2.0, 0.1, 0.1).radius == 0.25
