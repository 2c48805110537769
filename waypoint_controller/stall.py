"""Stall detection: notice when the robot stops getting closer to its waypoint."""

import math


class StallDetector:
    """
    Reports a stall when neither distance nor heading error has improved for a while.

    An improvement must beat the best value so far by a margin (1 cm, 1 degree), so a robot
    pressed against a wall, creeping by numerical noise, still counts as stalled.
    """

    def __init__(self, timeout: float, distance_margin: float = 0.01,
                 angle_margin: float = math.radians(1.0)):
        if timeout <= 0.0:
            raise ValueError(f'stall timeout must be positive, got {timeout}')
        self.timeout = timeout
        self._margins = (distance_margin, angle_margin)
        self.restart(0.0)

    def restart(self, now: float) -> None:
        """Start watching a new waypoint at time now (seconds)."""
        self._best = (math.inf, math.inf)
        self._last_progress = now

    def stalled(self, now: float, distance: float, angle_error: float) -> bool:
        """Record the errors at time now; return True once progress stopped for timeout."""
        improved = (distance < self._best[0] - self._margins[0]
                    or abs(angle_error) < self._best[1] - self._margins[1])
        if improved:
            self._best = (min(distance, self._best[0]), min(abs(angle_error), self._best[1]))
            self._last_progress = now
        return now - self._last_progress > self.timeout
