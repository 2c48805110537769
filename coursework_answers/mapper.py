"""
The reference mapper: an occupancy grid in log-odds, built from the laser alone. No ROS here.

Each scan adds its evidence cell by cell (courseworks.rays, compiled): the cells a ray crossed
before its return are more likely free, the return's cell more likely a wall. A cell no ray has
crossed stays unknown (-1), as nav_msgs/OccupancyGrid writes it; any other is its probability
of being occupied, 0 to 100. The grid has the world's geometry (the task gives it as the map's
metadata, never the map itself).
"""

import math

from courseworks.rays import integrate_ranges
import numpy as np

# Log-odds of one ray's evidence (a return: p 0.85; a ray through: p 0.4), clamped so a cell
# seen a thousand times still changes its mind within a few scans when the world does.
HIT = math.log(0.85 / 0.15)
MISS = math.log(0.4 / 0.6)
CLAMP = 4.0


class LogOddsMapper:
    """An occupancy grid of shape (rows, columns) at resolution, its cell (0, 0) at origin."""

    def __init__(self, shape: tuple[int, int], resolution: float,
                 origin: tuple[float, float]) -> None:
        self.resolution = resolution
        self.origin = origin
        self.log_odds = np.zeros(shape)
        self.observed = np.zeros(shape, dtype=bool)
        # Buffers of one scan's evidence, allocated once.
        self._free = np.zeros(shape, dtype=np.int32)
        self._walls = np.zeros(shape, dtype=np.int32)
        self._no_walls = np.zeros(shape, dtype=np.bool_)

    def add_scan(self, pose: tuple[float, float, float], first_angle: float, increment: float,
                 ranges: np.ndarray, max_range: float) -> None:
        """Add a scan taken from the laser's pose (x, y, theta), its ranges in metres."""
        self._free[:] = 0
        self._walls[:] = 0
        x, y, theta = pose
        integrate_ranges((x - self.origin[0]) / self.resolution,
                         (y - self.origin[1]) / self.resolution, theta, first_angle, increment,
                         np.asarray(ranges, dtype=float) / self.resolution,
                         max_range / self.resolution, self._free, self._walls, self._no_walls)
        # A cell counts once per scan, however many of its rays crossed it.
        free, walls = self._free > 0, self._walls > 0
        self.log_odds[free & ~walls] += MISS
        self.log_odds[walls] += HIT
        np.clip(self.log_odds, -CLAMP, CLAMP, out=self.log_odds)
        self.observed |= free | walls

    def cells(self) -> np.ndarray:
        """Return the grid as nav_msgs/OccupancyGrid's data: -1 unknown, else 0 to 100."""
        occupied = 1.0 - 1.0 / (1.0 + np.exp(self.log_odds))
        return np.where(self.observed, np.rint(100.0 * occupied), -1).astype(np.int8)
