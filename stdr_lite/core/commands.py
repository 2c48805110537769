"""Velocity commands as the simulator holds them between steps."""

import enum
import math

import numpy as np


class CommandOutcome(enum.Enum):
    """What became of a velocity command."""

    APPLIED = 'applied'
    CLAMPED = 'clamped to the speed limits'
    IGNORED = 'ignored: not finite'


class CommandBuffer:
    """
    The last valid (linear, angular) command of each robot, clamped to the speed limits.

    A command is held until the next one arrives, as in STDR. With a positive timeout, a robot
    whose last command is older than the timeout (in simulated seconds) is stopped.
    """

    def __init__(self, robot_count: int, max_linear_speed: float, max_angular_speed: float,
                 timeout: float = 0.0):
        self.max_linear_speed = float(max_linear_speed)
        self.max_angular_speed = float(max_angular_speed)
        self.timeout = float(timeout)
        self._linear = np.zeros(robot_count)
        self._angular = np.zeros(robot_count)
        self._received_at = np.zeros(robot_count)

    def update(self, index: int, linear: float, angular: float, now: float) -> bool:
        """
        Store a command; return False (and keep the previous one) if it is not finite.

        Values beyond the limits are clamped; the return value is True in that case as well.
        """
        if not (math.isfinite(linear) and math.isfinite(angular)):
            return False
        self._linear[index] = min(max(linear, -self.max_linear_speed), self.max_linear_speed)
        self._angular[index] = min(max(angular, -self.max_angular_speed), self.max_angular_speed)
        self._received_at[index] = now
        return True

    def add_robot(self) -> None:
        """Make room for one more robot, standing still."""
        self._linear = np.append(self._linear, 0.0)
        self._angular = np.append(self._angular, 0.0)
        self._received_at = np.append(self._received_at, 0.0)

    def remove_robot(self, index: int) -> None:
        """Forget robot index; the robots after it move down one index."""
        self._linear = np.delete(self._linear, index)
        self._angular = np.delete(self._angular, index)
        self._received_at = np.delete(self._received_at, index)

    def exceeds_limits(self, linear: float, angular: float) -> bool:
        """Whether a command would be clamped."""
        return abs(linear) > self.max_linear_speed or abs(angular) > self.max_angular_speed

    def current(self, now: float) -> tuple[np.ndarray, np.ndarray]:
        """Commands in force at time now, as (linear, angular) arrays."""
        if self.timeout <= 0.0:
            return self._linear.copy(), self._angular.copy()
        fresh = (now - self._received_at) <= self.timeout
        return np.where(fresh, self._linear, 0.0), np.where(fresh, self._angular, 0.0)
