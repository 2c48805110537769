"""The closed-form Reeds-Shepp paths: as short as OMPL's, and ending where they should."""

import math

import numpy as np
from ompl import base as ompl_base
import pytest
from waypoint_controller.reeds_shepp import (advance, LEFT, path_length, relative_goal, RIGHT,
                                             Segment, shortest_path, STRAIGHT)

RADIUS = 0.5


def end_of(start, segments):
    pose = start
    for segment in segments:
        pose = advance(pose, segment, abs(segment.length) * RADIUS, RADIUS)
    return pose


def random_poses(seed, count):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        start = tuple(rng.uniform([-3, -3, -math.pi], [3, 3, math.pi]))
        near = rng.random() < 0.3
        spread = 0.3 if near else 3.0
        goal = (start[0] + rng.uniform(-spread, spread), start[1] + rng.uniform(-spread, spread),
                rng.uniform(-math.pi, math.pi))
        yield start, goal


@pytest.mark.parametrize('seed', range(4))
def test_lengths_equal_ompl_and_paths_end_at_the_goal(seed):
    space = ompl_base.ReedsSheppStateSpace(RADIUS)
    first, second = space.allocState(), space.allocState()
    for start, goal in random_poses(seed, 500):
        first.setXY(*start[:2])
        first.setYaw(start[2])
        second.setXY(*goal[:2])
        second.setYaw(goal[2])
        segments = shortest_path(*relative_goal(start, goal, RADIUS))
        assert path_length(segments) * RADIUS == pytest.approx(space.distance(first, second),
                                                               abs=1e-9)
        end = end_of(start, segments)
        assert math.dist(end[:2], goal[:2]) < 1e-9
        assert abs(math.remainder(end[2] - goal[2], math.tau)) < 1e-9


def test_straight_ahead_and_straight_back():
    assert shortest_path(3.0, 0.0, 0.0) == (Segment(LEFT, 0.0), Segment(STRAIGHT, 3.0),
                                            Segment(LEFT, 0.0))
    backwards = shortest_path(-2.0, 0.0, 0.0)
    assert path_length(backwards) == pytest.approx(2.0)
    assert all(segment.length <= 0.0 for segment in backwards)


def test_a_quarter_turn_on_the_circle_is_one_arc():
    segments = shortest_path(1.0, 1.0, math.pi / 2)
    assert path_length(segments) == pytest.approx(math.pi / 2)
    assert [s.steering for s in segments if abs(s.length) > 1e-12] == [LEFT]
    assert path_length(shortest_path(1.0, -1.0, -math.pi / 2)) == pytest.approx(math.pi / 2)
    assert [s.steering for s in shortest_path(1.0, -1.0, -math.pi / 2)
            if abs(s.length) > 1e-12] == [RIGHT]


@pytest.mark.parametrize('requirement, seed, at_least', [('first_direction', 7, 500),
                                                         ('first_turn', 8, 300)])
def test_a_required_way_of_setting_off_is_kept_at_a_price(requirement, seed, at_least):
    """Forwards or backwards; turning counterclockwise or clockwise (or not at all) first."""
    kept = 0
    for start, goal in random_poses(seed, 300):
        relative = relative_goal(start, goal, RADIUS)
        free = shortest_path(*relative)
        for way in (1, -1):
            steady = shortest_path(*relative, **{requirement: way})
            if not steady:
                continue
            kept += 1
            first = next(s for s in steady if abs(s.length) > 1e-12)
            direction = math.copysign(1, first.length)
            assert (direction == way if requirement == 'first_direction'
                    else first.steering * direction in (0, way))
            assert path_length(steady) >= path_length(free) - 1e-12
            assert math.dist(end_of(start, steady)[:2], goal[:2]) < 1e-9
    assert kept > at_least
