"""
Unicycle kinematics: each integrator written once, compiled (numba), for one body or many.

euler_pose and arc_pose advance one body and are what the Bodies' compiled step calls;
euler_step and arc_step are the same functions over arrays, which broadcast: scalars for one
robot, arrays for many, or an extra trailing axis of durations to sample a step at several
instants (a polygon's path near a wall). Headings are wrapped by the one rule of
simple_robot_control.pose, compiled as it is.
"""

import math

from numba import njit
import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.compiled_rules import compiled
from simple_robot_control.pose import wrap_number
from stdr_lite.core.setting_values import ARC, EULER

wrap = compiled(wrap_number)


@njit(cache=True)
def euler_pose(x: float, y: float, theta: float, v: float, omega: float,
               dt: float) -> tuple:
    """
    Advance by dt with the lab's forward-Euler update (equation 2).

    The heading used for the translation is the one at the start of the step, exactly as the
    lab text writes it.
    """
    return (x + v * dt * math.cos(theta), y + v * dt * math.sin(theta),
            wrap(theta + omega * dt))


@njit(cache=True)
def arc_pose(x: float, y: float, theta: float, v: float, omega: float, dt: float) -> tuple:
    """
    Advance by dt along the exact constant-velocity arc.

    The chord has length v*dt*sin(h)/h, h being half the turn, and points along the mean
    heading; it is v*dt itself without a turn, so straight lines need no other case.
    """
    half_turn = 0.5 * omega * dt
    chord = v * dt * (math.sin(half_turn) / half_turn if half_turn != 0.0 else 1.0)
    mid_heading = theta + half_turn
    return (x + chord * math.cos(mid_heading), y + chord * math.sin(mid_heading),
            wrap(theta + omega * dt))


@njit(cache=True)
def integrate(x: float, y: float, theta: float, v: float, omega: float, dt: float,
              arc: bool) -> tuple:
    """Advance one body by the integrator chosen: the arc's if arc, else Euler's."""
    if arc:
        return arc_pose(x, y, theta, v, omega, dt)
    return euler_pose(x, y, theta, v, omega, dt)


def _over_arrays(pose):
    """Return pose over arrays: numpy broadcasting, each element through the compiled pose."""
    each = np.vectorize(pose, otypes=(float, float, float))

    def step(x: ArrayLike, y: ArrayLike, theta: ArrayLike, v: ArrayLike, omega: ArrayLike,
             dt: ArrayLike) -> tuple:
        return tuple(part[()] for part in each(x, y, theta, v, omega, dt))
    step.__doc__ = f'Advance any number of bodies as {pose.__name__} does (they broadcast).'
    return step


# Not numba ufuncs: those are compiled, or loaded from their cache, at every import (a second).
euler_step, arc_step = _over_arrays(euler_pose), _over_arrays(arc_pose)

INTEGRATORS = {EULER: euler_step, ARC: arc_step}
