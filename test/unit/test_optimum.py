"""bench/optimum.py on legs whose fastest time is known by hand."""

import math

from bench.optimum import course_optimum, ReedsSheppTimes, replay
import pytest
from waypoint_controller.config import ControllerConfig
from waypoint_lab.waypoints import Waypoint

CONFIG = ControllerConfig()
SPEED, RATE = CONFIG.max_linear_speed, CONFIG.max_angular_speed
TOLERANCE, ANGLE = CONFIG.distance_tolerance, CONFIG.angle_tolerance


def optimum(waypoint):
    return course_optimum((0.0, 0.0, 0.0), [waypoint], CONFIG, ReedsSheppTimes(CONFIG))


@pytest.mark.parametrize('waypoint, seconds', [
    (Waypoint(2.0, 0.0, 0.0), (2.0 - TOLERANCE) / SPEED),
    (Waypoint(-1.0, 0.0, 0.0), (1.0 - TOLERANCE) / SPEED),
    (Waypoint(0.0, 0.0, 2.0), (2.0 - ANGLE) / RATE),
])
def test_straight_behind_and_on_the_spot(waypoint, seconds):
    bound, chained, chain = optimum(waypoint)
    assert bound == pytest.approx(seconds)
    assert chained == pytest.approx(seconds)
    run = replay((0.0, 0.0, 0.0), [waypoint], chain, CONFIG, 0.05)
    assert run.success
    assert seconds <= run.time <= seconds + 0.1


def test_a_sidestep_beats_pivoting_by_reversing_on_the_way():
    sidestep = Waypoint(0.0, 0.6, 0.0)
    _, chained, _ = optimum(sidestep)
    pivot_drive_pivot = math.pi / RATE + (0.6 - TOLERANCE) / SPEED - 2 * ANGLE / RATE
    assert (0.6 - TOLERANCE) / SPEED < chained < pivot_drive_pivot


def test_a_chain_is_never_faster_than_its_bound():
    course = [Waypoint(1.0, 1.0, 1.0), Waypoint(1.0, 1.0, -1.0), Waypoint(-0.5, 1.2, 3.0)]
    bound, chained, chain = course_optimum((0.0, 0.0, 0.0), course, CONFIG,
                                           ReedsSheppTimes(CONFIG))
    assert bound <= chained + 1e-9
    assert len(chain) == len(course)
