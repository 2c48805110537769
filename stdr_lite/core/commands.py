"""Velocity commands as the simulator holds them between steps, and the limits they meet."""

import enum
import math

from numba import njit
import numpy as np
from stdr_lite.core.setting_values import SAFETY_ANGULAR_SPEED, SAFETY_LINEAR_SPEED
from stdr_lite.core.state import StateTable


class CommandOutcome(enum.Enum):
    """What became of a velocity command."""

    APPLIED = 'applied'
    CLAMPED = 'clamped to the speed limits'
    SAFETY_BOUND = 'clamped to the safety bound'
    NOT_OMNI = 'applied without its linear.y: the robot is not omni-directional'
    IGNORED = 'ignored: not finite'


def speed_limits(max_linear_speed: float, max_angular_speed: float,
                 safety: tuple[float, float] = (SAFETY_LINEAR_SPEED, SAFETY_ANGULAR_SPEED)
                 ) -> tuple[float, float]:
    """Return the limits in force: a limit of 0 is none (as STDR), short of the safety bound."""
    return (min(max_linear_speed or safety[0], safety[0]),
            min(max_angular_speed or safety[1], safety[1]))


class HeldCommands:
    """
    The last valid (linear, lateral, angular) command of each robot, within the speed limits.

    They are held in the state's command and commanded_at columns (state.py).

    linear and lateral are the robot-frame velocity (lateral is an omni robot's linear.y), whose
    length is clamped to max_linear_speed; angular to max_angular_speed. A limit of 0 is none
    (short of the safety bound, safety: linear and angular). A command is held until the next
    one arrives, as in STDR. With a positive timeout, a robot whose last command is older than
    the timeout (in simulated seconds) is stopped.
    """

    def __init__(self, state: StateTable, max_linear_speed: float, max_angular_speed: float,
                 timeout: float = 0.0,
                 safety: tuple[float, float] = (SAFETY_LINEAR_SPEED, SAFETY_ANGULAR_SPEED)):
        self.state = state
        self.clamps = bool(max_linear_speed or max_angular_speed)
        self.safety = safety
        self.max_linear_speed, self.max_angular_speed = speed_limits(
            max_linear_speed, max_angular_speed, safety)
        self.timeout = float(timeout)

    def limited(self, linear: float, lateral: float,
                angular: float) -> tuple[tuple[float, float, float], CommandOutcome]:
        """Return a finite command within the limits, and whether (and why) it was clamped."""
        command = _limit(linear, lateral, angular, self.max_linear_speed,
                         self.max_angular_speed)
        if command == (linear, lateral, angular):
            return command, CommandOutcome.APPLIED
        at_bound = (math.hypot(linear, lateral) > self.safety[0]
                    or abs(angular) > self.safety[1])
        outcome = (CommandOutcome.SAFETY_BOUND if at_bound and not self.clamps
                   else CommandOutcome.CLAMPED)
        return command, outcome

    def limited_rows(self, commands: np.ndarray) -> np.ndarray:
        """Return (linear, lateral, angular) rows within the limits, as limited() makes each."""
        return _limit_rows(np.ascontiguousarray(commands, dtype=float), self.max_linear_speed,
                           self.max_angular_speed)

    def update_rows(self, indices: np.ndarray, commands: np.ndarray, now: float) -> None:
        """Hold each row of commands for the robot of the same row of indices from now on."""
        self.state.command[indices] = commands
        self.state.commanded_at[indices] = now

    def update(self, index: int, command: tuple[float, float, float], now: float) -> None:
        """Hold command (linear, lateral, angular) for robot index from now on."""
        self.state.command[index] = command
        self.state.commanded_at[index] = now

    def current(self, now: float) -> np.ndarray:
        """Return the commands in force at time now, a new (linear, lateral, angular) row each."""
        if self.timeout > 0.0:
            return np.where(((now - self.state.commanded_at) <= self.timeout)[:, None],
                            self.state.command, 0.0)
        return self.state.command.copy()


@njit(cache=True)
def _limit(linear, lateral, angular, max_linear_speed, max_angular_speed):
    """
    Return a command within the limits: the speed scaled down to the limit, the turn clipped.

    The one rule of both limited() and limited_rows(); a command within them is kept as it is
    (which is how limited() knows it was within them).
    """
    speed = math.hypot(linear, lateral)
    if speed <= max_linear_speed and abs(angular) <= max_angular_speed:
        return linear, lateral, angular
    scale = min(1.0, max_linear_speed / speed) if speed > 0.0 else 1.0
    return (linear * scale, lateral * scale,
            min(max(angular, -max_angular_speed), max_angular_speed))


@njit(cache=True)
def _limit_rows(commands, max_linear_speed, max_angular_speed):
    limited = np.empty_like(commands)
    for row in range(commands.shape[0]):
        limited[row, 0], limited[row, 1], limited[row, 2] = _limit(
            commands[row, 0], commands[row, 1], commands[row, 2], max_linear_speed,
            max_angular_speed)
    return limited
