"""
Unicycle kinematics, vectorized over any number of robots.

Every function broadcasts: pass scalars for one robot, arrays for many, or an extra trailing
axis of durations to sample a step at several instants. The *_one twins do the same for one
robot in plain Python floats, to the last bit (numpy's sin, cos and remainder are the C
library's; wrap_angle is one rule for both), at a fraction of numpy's per-call cost.
"""

import math

import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.pose import wrap_angle
from stdr_lite.core.setting_values import ARC, EULER


def euler_step(x: ArrayLike, y: ArrayLike, theta: ArrayLike, v: ArrayLike, omega: ArrayLike,
               dt: ArrayLike) -> tuple:
    """
    Advance by dt with the lab's forward-Euler update (equation 2).

    The heading used for the translation is the one at the start of the step, exactly as the
    lab text writes it.
    """
    return (x + v * dt * np.cos(theta),
            y + v * dt * np.sin(theta),
            wrap_angle(theta + omega * dt))


def arc_step(x: ArrayLike, y: ArrayLike, theta: ArrayLike, v: ArrayLike, omega: ArrayLike,
             dt: ArrayLike) -> tuple:
    """
    Advance by dt along the exact constant-velocity arc.

    The chord has length v*dt*sinc(omega*dt/2) and points along the mean heading, which stays
    finite as omega goes to zero, so straight lines need no special case.
    """
    half_turn = 0.5 * omega * dt
    chord = v * dt * np.sinc(half_turn / np.pi)
    mid_heading = theta + half_turn
    return (x + chord * np.cos(mid_heading),
            y + chord * np.sin(mid_heading),
            wrap_angle(theta + omega * dt))


def euler_step_one(x: float, y: float, theta: float, v: float, omega: float,
                   dt: float) -> tuple[float, float, float]:
    """Advance one robot as euler_step does."""
    return (x + v * dt * math.cos(theta),
            y + v * dt * math.sin(theta),
            wrap_angle(theta + omega * dt))


def arc_step_one(x: float, y: float, theta: float, v: float, omega: float,
                 dt: float) -> tuple[float, float, float]:
    """Advance one robot as arc_step does (numpy's sinc: sin(pi t) / (pi t), 1 at 0)."""
    half_turn = 0.5 * omega * dt
    scaled = math.pi * (half_turn / math.pi if half_turn != 0.0 else 1e-20)
    chord = v * dt * (math.sin(scaled) / scaled)
    mid_heading = theta + half_turn
    return (x + chord * math.cos(mid_heading),
            y + chord * math.sin(mid_heading),
            wrap_angle(theta + omega * dt))


INTEGRATORS = {EULER: euler_step, ARC: arc_step}
INTEGRATORS_ONE = {EULER: euler_step_one, ARC: arc_step_one}
