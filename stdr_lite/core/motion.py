"""What a velocity set from outside (a standard SetEntityState) means for each kind of entity."""

from dataclasses import dataclass
import math

from simple_robot_control.validation import compact
from stdr_lite.core.entities import Category, RequestError, SimulationSettings

# Sideways speed a unicycle cannot take, m/s: anything beyond rounding.
SIDEWAYS = 1e-9


@dataclass(frozen=True)
class Motion:
    """
    How to move an entity.

    A robot's command (linear along its heading, angular) has heading None; an obstacle's
    slide is its speed along heading in the map frame, and its angular velocity.
    """

    linear: float
    angular: float
    heading: float | None = None


def motion_for(category: Category, theta: float, x: float, y: float, angular: float,
               settings: SimulationSettings) -> Motion:
    """
    Return how an entity facing theta follows the map-frame velocity (x, y, angular).

    Raises RequestError for a velocity that is not finite or beyond the limits, a sideways
    velocity for a robot (a unicycle), or any velocity for a static obstacle.
    """
    if not all(map(math.isfinite, (x, y, angular))):
        raise RequestError('the velocity must be finite')
    speed = math.hypot(x, y)
    if speed > settings.max_linear_speed or abs(angular) > settings.max_angular_speed:
        raise RequestError(f'the velocity exceeds the limits ({compact(speed)} m/s, '
                           f'{compact(angular)} rad/s; at most '
                           f'{compact(settings.max_linear_speed)} m/s and '
                           f'{compact(settings.max_angular_speed)} rad/s)')
    if category is Category.STATIC_OBSTACLE:
        if speed or angular:
            raise RequestError('a static obstacle does not move; spawn a moving_obstacle')
        return Motion(0.0, 0.0, 0.0)
    if category is Category.ROBOT:
        if abs(-x * math.sin(theta) + y * math.cos(theta)) > SIDEWAYS:
            raise RequestError(f'a robot is a unicycle: it moves along its heading only (theta '
                               f'{compact(round(theta, 4))}: x = v cos theta, y = v sin theta)')
        return Motion(x * math.cos(theta) + y * math.sin(theta), angular)
    return Motion(speed, angular, math.atan2(y, x))
