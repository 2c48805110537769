"""
When a run of the lab may take its first odometry: apart from the running, and free of ROS.

A controller holds the odometry that comes before it may start: until discovery has had its
grace (to see who else commands the robot), and, when its law plans around walls and the map
topic has a publisher, until the map is in (at most MAP_WAIT seconds), so the first plan
already avoids the walls. Only the latest odometry is held; it is answered once the run may go.
"""

from collections.abc import Callable
import time
from typing import Any

MAP_WAIT = 10.0


class StartConditions:
    """
    Whether the run may start, and the odometry held until it may.

    map_publishers() counts the map topic's publishers (None: the law takes no map); warn
    receives the one line said when the map is given up on; clock gives seconds.
    """

    def __init__(self, map_topic: str, map_publishers: Callable[[], int] | None,
                 warn: Callable[[str], None], clock: Callable[[], float] = time.monotonic):
        self._map_topic, self._map_publishers, self._warn = map_topic, map_publishers, warn
        self._clock = clock
        self._since = clock()
        self._discovered = self._has_map = self._map_given_up = False
        self._held = None

    @property
    def has_map(self) -> bool:
        """Whether a map has come."""
        return self._has_map

    def discovered(self) -> None:
        """Note that discovery has had its grace."""
        self._discovered = True

    def map_came(self) -> None:
        """Note that a readable map came: the law knows the walls."""
        self._has_map = True

    def map_unreadable(self) -> None:
        """Wait for the map no more: what came on the map topic is no map."""
        self._map_given_up = True

    def may_start(self) -> bool:
        """Whether discovery has had its grace and the walls are known, or cannot be."""
        if not self._discovered:
            return False
        if (self._map_publishers is None or self._has_map or self._map_given_up
                or self._map_publishers() == 0):
            return True
        waited = self._clock() - self._since
        if waited < MAP_WAIT:
            return False
        self._map_given_up = True
        self._warn(f'{self._map_topic} has a publisher but no map came in {waited:.0f} s: '
                   'driving without regard to walls until it does')
        return True

    def hold(self, message: Any) -> None:
        """Keep message (the latest odometry) until the run may start."""
        self._held = message

    def release(self) -> Any | None:
        """Return the odometry held, once the run may start (then no more); else None."""
        if self._held is None or not self.may_start():
            return None
        held, self._held = self._held, None
        return held
