"""
The courses the task draws: what the lab's courses hold, and more. No ROS here.

Each waypoint follows the previous one (or the start) as one of these, drawn in turn:

    turn in place    TURN     the same position, a new heading
    revisit          REVISIT  the position of an earlier waypoint or of the start
    short leg        SHORT    within course_step (3 m) of the previous position
    long leg         (else)   anywhere on the map (the lab room: legs up to 24 m)

and, a leg's end, NEAR_WALL of the time only near_wall (5 cm) beyond the robot's disc from a
wall, else clearance (0.4 m). Headings are uniform. The bundled courses (back-ups, a tour, turns
in place, a square, headings across +-180 degrees) are all of this distribution.
"""

from __future__ import annotations

from collections.abc import Callable
import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # task.py's settings; the task draws its courses from here
    from waypoint_lab.learning.task import TaskSettings

TURN = 0.1
REVISIT = 0.1
SHORT = 0.4
NEAR_WALL = 0.25
ATTEMPTS = 10_000


def sample_course(rng: np.random.Generator, is_free: Callable, start: tuple,
                  settings: TaskSettings,
                  bounds: tuple, radius: float) -> np.ndarray:
    """
    Draw a course of settings.waypoints waypoints (K x 3) from start.

    is_free(x, y, clearance) says whether a disc of clearance fits at (x, y); bounds is the
    map's (x_min, y_min, x_max, y_max); radius the robot's. A leg whose end cannot be placed
    after many attempts turns in place instead.
    """
    visited = [(start[0], start[1])]
    waypoints = []
    for _ in range(settings.waypoints):
        x, y = visited[-1]
        kind = rng.uniform()
        if kind < TURN + REVISIT:
            if kind >= TURN and len(visited) > 1:
                x, y = visited[int(rng.integers(len(visited) - 1))]
        else:
            near = rng.uniform() < NEAR_WALL
            clearance = radius + (settings.near_wall if near else settings.clearance)
            reach = settings.course_step if kind < TURN + REVISIT + SHORT else None
            x, y = _leg_end(rng, is_free, (x, y), reach, bounds, clearance)
        visited.append((x, y))
        waypoints.append((x, y, rng.uniform(-math.pi, math.pi)))
    return np.array(waypoints)


def sample_position(rng: np.random.Generator, is_free: Callable, bounds: tuple,
                    clearance: float,
                    fallback: tuple) -> tuple:
    """Draw a position anywhere on the map where a disc of clearance fits (else fallback)."""
    return _leg_end(rng, is_free, fallback, None, bounds, clearance)


def _leg_end(rng, is_free, origin, reach, bounds, clearance):
    """Return a free position within reach of origin (anywhere if reach is None), or origin."""
    x_min, y_min, x_max, y_max = bounds
    for _ in range(ATTEMPTS):
        if reach is None:
            candidate = (rng.uniform(x_min, x_max), rng.uniform(y_min, y_max))
        else:
            angle, length = rng.uniform(-math.pi, math.pi), rng.uniform(0.0, reach)
            candidate = (origin[0] + length * math.cos(angle),
                         origin[1] + length * math.sin(angle))
        if is_free(*candidate, clearance):
            return candidate
    return origin
