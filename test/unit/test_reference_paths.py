"""The benchmark's reference paths end exactly at their goal and take the time they claim."""

import math

from bench.reference_paths import candidate_paths, follow
import numpy as np
import pytest


@pytest.mark.parametrize('seed', range(5))
def test_every_candidate_path_reaches_its_goal(seed):
    rng = np.random.default_rng(seed)
    for _ in range(100):
        start = tuple(rng.uniform([-2, -2, -math.pi], [2, 2, math.pi]))
        goal = tuple(rng.uniform([-2, -2, -math.pi], [2, 2, math.pi]))
        paths = candidate_paths(start, goal, (0.5, 0.2))
        assert {path.name for path in paths} >= {'rotate-straight-rotate'}
        for path in paths:
            end, _ = follow(start, path, math.inf, 0.5, 1.0)
            assert math.dist(end[:2], goal[:2]) < 1e-6, path
            assert abs(math.remainder(end[2] - goal[2], math.tau)) < 1e-6, path


def test_duration_is_when_the_path_ends():
    goal = (2.0, 1.0, 1.0)
    for path in candidate_paths((0.0, 0.0, 0.0), goal, (0.5,)):
        duration = path.duration(0.5, 1.0)
        end, _ = follow((0.0, 0.0, 0.0), path, duration, 0.5, 1.0)
        almost, _ = follow((0.0, 0.0, 0.0), path, 0.999 * duration, 0.5, 1.0)
        assert math.dist(end[:2], goal[:2]) < 1e-6, path
        assert abs(math.remainder(end[2] - goal[2], math.tau)) < 1e-6, path
        assert math.dist(almost[:2], end[:2]) + abs(almost[2] - end[2]) > 1e-6, path


def test_a_straight_goal_is_one_straight_line():
    paths = candidate_paths((0.0, 0.0, 0.0), (3.0, 0.0, 0.0), (0.5,))
    fastest = min(paths, key=lambda path: path.duration(0.5, 1.0))
    assert fastest.duration(0.5, 1.0) == pytest.approx(6.0)
    assert not fastest.backward
