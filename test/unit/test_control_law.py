"""The control law in a plain kinematic loop: each behaviour the issue asks for."""

import math

import pytest
from stdr_lite.core.kinematics import arc_step
from waypoint_controller.control_law import (ControllerConfig, CourseFollower, in_goal_set,
                                             PoseController, wrap)
from waypoint_controller.waypoints import Waypoint

CONFIG = ControllerConfig()


def simulate(waypoints, start, dt=0.05, time_limit=60.0):
    """Drive the course with exact arcs; return the trace of (time, pose, step) and the time."""
    follower = CourseFollower(waypoints, CONFIG)
    pose, trace, elapsed = start, [], 0.0
    while elapsed <= time_limit:
        step = follower.update(pose, dt)
        trace.append((elapsed, pose, step))
        if step.finished:
            return trace, elapsed
        pose = tuple(float(value) for value in arc_step(*pose, step.linear, step.angular, dt))
        elapsed += dt
    raise AssertionError(f'course not finished within {time_limit} s')


def reach_poses(trace):
    return [(pose, index) for _, pose, step in trace for index in step.reached]


def test_reported_poses_lie_in_their_goal_sets():
    waypoints = [Waypoint(2, 1, 1.0), Waypoint(0, 2, 3.0), Waypoint(-1, -1, -2.0)]
    trace, _ = simulate(waypoints, (0.0, 0.0, 0.0))
    reached = reach_poses(trace)
    assert [index for _, index in reached] == [0, 1, 2]
    for pose, index in reached:
        assert in_goal_set(pose, waypoints[index], CONFIG)


def test_commands_respect_the_limits():
    trace, _ = simulate([Waypoint(3, -2, 2.5), Waypoint(-1, 1, -1.0)], (0.0, 0.0, 0.0))
    assert max(abs(step.linear) for _, _, step in trace) <= CONFIG.max_linear_speed
    assert max(abs(step.angular) for _, _, step in trace) <= CONFIG.max_angular_speed


def test_goal_directly_behind_is_reached_backing_up():
    trace, elapsed = simulate([Waypoint(-0.8, 0.0, 0.0)], (0.0, 0.0, 0.0))
    assert all(step.linear <= 0.0 for _, _, step in trace)
    assert max(abs(pose[2]) for _, pose, _ in trace) < math.radians(10)
    assert elapsed < 0.8 / CONFIG.max_linear_speed + 1.0


def test_goal_inside_the_turning_circle_is_never_orbited():
    goal = Waypoint(0.15, 0.3, math.pi / 2)
    trace, _ = simulate([goal], (0.0, 0.0, 0.0))
    distances = [math.hypot(goal.x - pose[0], goal.y - pose[1]) for _, pose, _ in trace]
    assert all(later <= earlier + 1e-9 for earlier, later in zip(distances, distances[1:]))


def test_pure_rotation_turns_in_place_at_full_rate():
    trace, elapsed = simulate([Waypoint(0.0, 0.0, 2.0)], (0.0, 0.0, 0.0))
    assert all(step.linear == 0.0 for _, _, step in trace)
    assert elapsed == pytest.approx((2.0 - CONFIG.angle_tolerance) / CONFIG.max_angular_speed,
                                    abs=0.05 + 1e-9)


def test_heading_across_180_degrees_takes_the_short_way():
    trace, elapsed = simulate([Waypoint(0.0, 0.0, math.radians(179))],
                              (0.0, 0.0, math.radians(-170)))
    assert elapsed <= math.radians(6) / CONFIG.max_angular_speed + 0.05
    assert all(step.angular <= 0.0 for _, _, step in trace)


def test_waypoint_at_the_current_pose_is_reached_at_once():
    follower = CourseFollower([Waypoint(1.0, 2.0, 0.5)], CONFIG)
    step = follower.update((1.0, 2.0, 0.5), 0.05)
    assert step.reached == (0,) and step.finished
    assert (step.linear, step.angular) == (0.0, 0.0)


def test_intermediate_waypoints_are_passed_without_stopping():
    waypoints = [Waypoint(2.0, 0.0, 0.0), Waypoint(4.0, 0.0, 0.0), Waypoint(6.0, 0.0, 0.0)]
    trace, elapsed = simulate(waypoints, (0.0, 0.0, 0.0))
    for _, _, step in trace:
        if step.reached and not step.finished:
            assert step.linear > 0.9 * CONFIG.max_linear_speed
    assert elapsed < (6.0 - CONFIG.distance_tolerance) / CONFIG.max_linear_speed + 0.1


def test_final_rotation_brakes_onto_the_heading_without_reversing():
    trace, _ = simulate([Waypoint(1.5, 0.0, 2.5)], (0.0, 0.0, 0.0))
    rotating = [step.angular for _, pose, step in trace
                if math.hypot(1.5 - pose[0], pose[1]) <= CONFIG.distance_tolerance]
    assert all(rate >= 0.0 for rate in rotating)


def test_rotation_mode_has_hysteresis():
    controller = PoseController(CONFIG)
    goal = Waypoint(0.0, 0.0, 1.0)
    controller.start((0.04, 0.0, 0.0), goal)
    controller.command((0.04, 0.0, 0.0), 0.05)
    assert controller.rotating
    controller.command((0.08, 0.0, 0.0), 0.05)
    assert controller.rotating
    controller.command((0.095, 0.0, 0.0), 0.05)
    assert not controller.rotating


@pytest.mark.parametrize('dt', [0.2, 0.01])
def test_works_from_5_to_100_hz(dt):
    waypoints = [Waypoint(2.0, 1.0, 1.5), Waypoint(1.0, 2.5, -3.0), Waypoint(1.0, 2.5, 0.0),
                 Waypoint(0.3, 2.5, 0.0)]
    trace, _ = simulate(waypoints, (0.0, 0.0, 0.0), dt=dt)
    assert [index for _, index in reach_poses(trace)] == [0, 1, 2, 3]


def test_wrap_lands_in_half_open_interval():
    assert wrap(math.pi) == math.pi and wrap(-math.pi) == math.pi
    assert wrap(3 * math.pi / 2) == pytest.approx(-math.pi / 2)


def test_bad_configuration_is_refused():
    with pytest.raises(ValueError, match='max_linear_speed must be positive'):
        PoseController(ControllerConfig(max_linear_speed=0.0))
    with pytest.raises(ValueError, match='rotate_radius'):
        PoseController(ControllerConfig(rotate_radius=0.95))


def test_given_direction_and_gain_are_kept():
    controller = PoseController(CONFIG)
    controller.start((0.0, 0.0, 0.0), Waypoint(3.0, 0.0, 0.0), backward=True, approach_gain=2.0)
    assert (controller.backward, controller.approach_gain) == (True, 2.0)
    linear, _ = controller.command((0.0, 0.0, 0.0), 0.05)
    assert linear == 0.0


def test_a_goal_ahead_is_driven_to_forwards():
    controller = PoseController(CONFIG)
    controller.start((0.0, 0.0, 0.0), Waypoint(3.0, 0.5, 0.3))
    assert not controller.backward


def test_errors_are_measured_to_the_current_waypoint():
    follower = CourseFollower([Waypoint(3.0, 4.0, math.radians(170))], CONFIG)
    distance, heading_error = follower.errors((0.0, 0.0, math.radians(-170)))
    assert distance == pytest.approx(5.0)
    assert heading_error == pytest.approx(math.radians(-20))


def test_pivoting_turns_in_place_until_the_goal_is_ahead_then_drives():
    controller = PoseController(CONFIG)
    controller.start((0.0, 0.0, 0.0), Waypoint(0.0, 1.0, 0.0), backward=False,
                     approach_gain=0.0, pivot=math.radians(5.0))
    pose, commands = (0.0, 0.0, 0.0), []
    while len(commands) < 60:
        linear, angular = controller.command(pose, 0.05)
        commands.append((linear, angular))
        pose = tuple(float(value) for value in arc_step(*pose, linear, angular, 0.05))
    turning = [command for command in commands if command[0] == 0.0]
    assert commands[:len(turning)] == turning
    assert all(angular == pytest.approx(CONFIG.max_angular_speed) for _, angular in turning[:-1])
    assert commands[len(turning)][0] > 0.0
    assert abs(wrap(math.pi / 2 - pose[2])) < math.radians(10)


def test_a_sidestep_is_taken_by_pivoting_and_faster_than_by_curving():
    sidestep = Waypoint(0.0, 0.6, 0.0)
    controller = PoseController(CONFIG)
    controller.start((0.0, 0.0, 0.0), sidestep)
    assert controller.pivoting is not None
    _, elapsed = simulate([sidestep], (0.0, 0.0, 0.0))
    curving = PoseController(CONFIG)
    curving.waypoint = sidestep
    quickest_curve = min(curving._predict((0.0, 0.0, 0.0), backward, gain, None, math.inf)
                         for backward in (False, True) for gain in (0.0, 0.25, 0.75, 2.0))
    assert elapsed < quickest_curve - 1.0
