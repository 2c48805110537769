"""
How velocities become motion, and STDR's motion noise on a robot's commands.

A velocity set from outside (a standard SetEntityState) means something for each kind of
entity. No ROS here.
"""

from dataclasses import dataclass
import math

import numpy as np
from simple_robot_control.validation import compact
from stdr_lite.core.commands import speed_limits
from stdr_lite.core.entities import Category, RequestError, SimulationSettings

# Sideways speed a unicycle cannot take, m/s: anything beyond rounding.
SIDEWAYS = 1e-9


@dataclass(frozen=True)
class Motion:
    """
    How to move an entity.

    A robot's command (linear along its heading, lateral to its left, angular) has heading
    None; an obstacle's slide is its speed along heading in the map frame, and its angular
    velocity.
    """

    linear: float
    angular: float
    heading: float | None = None
    lateral: float = 0.0


def motion_for(category: Category, theta: float, x: float, y: float, angular: float,
               settings: SimulationSettings, omni: bool = False) -> Motion:
    """
    Return how an entity facing theta follows the map-frame velocity (x, y, angular).

    Raises RequestError for a velocity that is not finite or beyond the limits, a sideways
    velocity for a robot that is not omni-directional (a unicycle), or any velocity for a
    static obstacle.
    """
    if not all(map(math.isfinite, (x, y, angular))):
        raise RequestError('the velocity must be finite')
    speed = math.hypot(x, y)
    max_linear, max_angular = speed_limits(settings.max_linear_speed, settings.max_angular_speed,
                                           settings.safety)
    if speed > max_linear or abs(angular) > max_angular:
        raise RequestError(f'the velocity exceeds the limits ({compact(speed)} m/s, '
                           f'{compact(angular)} rad/s; at most {compact(max_linear)} m/s and '
                           f'{compact(max_angular)} rad/s)')
    if category is Category.STATIC_OBSTACLE:
        if speed or angular:
            raise RequestError('a static obstacle does not move; spawn a moving_obstacle')
        return Motion(0.0, 0.0, 0.0)
    if category is Category.ROBOT:
        forward = x * math.cos(theta) + y * math.sin(theta)
        sideways = -x * math.sin(theta) + y * math.cos(theta)
        if omni:
            return Motion(forward, angular, lateral=sideways)
        if abs(sideways) > SIDEWAYS:
            raise RequestError(f'a robot is a unicycle: it moves along its heading only (theta '
                               f'{compact(round(theta, 4))}: x = v cos theta, y = v sin theta)')
        return Motion(forward, angular)
    return Motion(speed, angular, math.atan2(y, x))


def noisy_command(command: tuple[float, float, float], parameters: tuple,
                  rng: np.random.Generator) -> tuple[float, float, float]:
    """
    Return a command (u_x, u_y, w) as STDR's motion noise makes it, sampled once per command.

    parameters are a_ux_ux ... a_g_w in the order of KINEMATIC_PARAMETERS: u_x takes
    N(0, a_ux_ux u_x^2 + a_ux_uy u_y^2 + a_ux_w w^2) (a variance), u_y and w likewise, and w
    an extra turn g drawn the same way.
    """
    squares = np.square(command)
    variances = np.asarray(parameters, dtype=float).reshape(4, 3) @ squares
    ux, uy, w, g = rng.normal(0.0, np.sqrt(variances))
    return command[0] + ux, command[1] + uy, command[2] + w + g
