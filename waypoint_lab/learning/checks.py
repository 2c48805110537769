"""
What the learning environments are given, checked whole: one ValueError naming key and value.

Every door of the project checks its input; these are the learning environments' (settings,
reset options, starts, courses, agents, actions), so that a NaN waypoint, a course of the
wrong length, a heading in degrees or an action of the wrong shape is one clear line rather
than NaN observations, a numpy broadcasting error or an action silently reshaped. No ROS here.
"""

import math
from numbers import Integral, Real

import numpy as np
from waypoint_lab.learning.task import TaskSettings

# A heading is in radians; beyond a turn either way it is most likely in degrees.
MAX_HEADING = 2 * math.pi
OPTION_KEYS = ('start', 'waypoints')


def count(name: str, value: object, low: int = 1) -> int:
    """Return value as an int of at least low, or raise ValueError naming it."""
    if isinstance(value, bool) or not isinstance(value, Integral) or value < low:
        raise ValueError(f'{name} must be a whole number of at least {low}, got {value!r}')
    return int(value)


def positive(name: str, value: object, at_most: float = math.inf) -> float:
    """Return value as a finite float above 0 (and at most at_most), or raise ValueError."""
    if (isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value)
            or not 0 < value <= at_most):
        bound = '' if at_most == math.inf else f' and at most {at_most:g}'
        raise ValueError(f'{name} must be a finite number above 0{bound}, got {value!r}')
    return float(value)


def numbers(name: str, value: object, shape: tuple) -> np.ndarray:
    """
    Return value as a float array of exactly shape, every element finite, or raise.

    Actions go through it too: a NaN action is refused, never driven.
    """
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be numbers of shape {shape}, got {value!r}') from None
    if array.shape != shape:
        raise ValueError(f'{name} must have shape {shape}, got {array.shape}: {value!r}')
    if not np.isfinite(array).all():
        raise ValueError(f'{name} must be finite, got {value!r}')
    return array


def poses(name: str, value: object, rows: int | None = None) -> np.ndarray:
    """Return one pose, or rows of them, as (x, y, theta) checked; theta within a turn."""
    array = numbers(name, value, (3,) if rows is None else (rows, 3))
    headings = array[..., 2]
    if (np.abs(headings) > MAX_HEADING).any():
        raise ValueError(f'{name}: a heading is in radians, within ±{MAX_HEADING:.4f}; got '
                         f'{value!r}')
    return array


def task(waypoints: object, distance_tolerance: float, angle_tolerance: float,
         laser_rays: object,
         max_linear_speed: float, max_angular_speed: float, random_start: bool) -> TaskSettings:
    """Return the task of an environment's parameters (angle_tolerance in degrees), checked."""
    return TaskSettings(
        count('waypoints', waypoints), positive('distance_tolerance', distance_tolerance),
        math.radians(positive('angle_tolerance', angle_tolerance, at_most=180.0)),
        count('laser_rays', laser_rays), positive('max_linear_speed', max_linear_speed),
        positive('max_angular_speed', max_angular_speed), random_start=bool(random_start))


def options(given: object, keys: tuple = OPTION_KEYS) -> dict:
    """Return reset options as a dict, refusing any key but keys."""
    if given is None:
        return {}
    if not isinstance(given, dict):
        raise ValueError(f'options must be a dict with keys among {keys}, got {given!r}')
    unknown = sorted(set(given) - set(keys), key=str)
    if unknown:
        raise ValueError(f'options: unknown key {unknown[0]!r}: the keys are {", ".join(keys)}')
    return given


def per_agent(given: object, agents: list) -> dict:
    """Return PettingZoo reset options ({key: {agent: value}}), refusing unknown agents."""
    checked = options(given)
    for key, values in checked.items():
        if not isinstance(values, dict):
            raise ValueError(f"options['{key}'] must map agents to values, got {values!r}")
        unknown = sorted(set(values) - set(agents), key=str)
        if unknown:
            raise ValueError(f"options['{key}']: no agent {unknown[0]!r}: the agents are "
                             f'{", ".join(agents)}')
    return checked
