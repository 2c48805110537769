"""
Exact footprint-versus-grid checks for circular robots.

A circle touches an occupied cell when its centre is closer than its radius to the cell's
square. A precomputed mask marks the cells where no circle of the largest radius can touch
anything, so robots in open space cost one lookup and only robots near a wall pay for the
exact check against the cells around them. Everything outside the map counts as occupied.
A second mask, wider by MOTION_MARGIN, lets a short step in open space skip the check along
its path altogether.
"""

import math

import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.occupancy_map import OccupancyMap

MOTION_MARGIN = 0.1
CELLS_PER_BATCH = 1 << 22


class FootprintChecker:
    """Answers whether circles at given positions touch an occupied cell or leave the map."""

    def __init__(self, occupancy_map: OccupancyMap, max_radius: float):
        if max_radius <= 0.0:
            raise ValueError(f'robot radius must be positive, got {max_radius}')
        self.resolution = occupancy_map.resolution
        self.max_radius = float(max_radius)
        origin_x, origin_y, yaw = occupancy_map.origin
        self._origin = (origin_x, origin_y)
        self._cos_yaw, self._sin_yaw = math.cos(yaw), math.sin(yaw)
        self._height, self._width = occupancy_map.occupied.shape
        self._reach = math.ceil(self.max_radius / self.resolution)
        self._pad = math.ceil((self.max_radius + MOTION_MARGIN) / self.resolution)
        self._padded = np.pad(occupancy_map.occupied, self._pad, constant_values=True)
        steps = np.arange(-self._reach, self._reach + 1)
        rows, cols = np.meshgrid(steps, steps, indexing='ij')
        self._window_rows, self._window_cols = rows.ravel(), cols.ravel()
        self._near_obstacle = self._cells_within(self.max_radius)
        self._near_for_motion = self._cells_within(self.max_radius + MOTION_MARGIN)

    def _cells_within(self, distance):
        """Mark cells from which some point could lie within distance of an occupied cell."""
        reach, pad = math.ceil(distance / self.resolution), self._pad
        near = np.zeros((self._height, self._width), dtype=bool)
        for row_step in range(-reach, reach + 1):
            for col_step in range(-reach, reach + 1):
                gap = self.resolution * math.hypot(max(abs(row_step) - 1, 0),
                                                   max(abs(col_step) - 1, 0))
                if gap < distance:
                    near |= self._padded[pad + row_step:pad + row_step + self._height,
                                         pad + col_step:pad + col_step + self._width]
        return near

    def _cells(self, x, y):
        map_x, map_y = self.to_map_frame(x, y)
        cols = np.floor(map_x / self.resolution).astype(np.int64)
        rows = np.floor(map_y / self.resolution).astype(np.int64)
        inside = (rows >= 0) & (rows < self._height) & (cols >= 0) & (cols < self._width)
        return map_x, map_y, rows, cols, inside

    def clear_for_motion(self, x: ArrayLike, y: ArrayLike, step_length: ArrayLike) -> np.ndarray:
        """
        Whether a circle of max_radius starting at (x, y) surely touches nothing on a path.

        True only where the path is at most MOTION_MARGIN long and starts in open space; False
        means the path must be checked.
        """
        _, _, rows, cols, inside = self._cells(x, y)
        clear = inside & (np.asarray(step_length) <= MOTION_MARGIN)
        clear[clear] = ~self._near_for_motion[rows[clear], cols[clear]]
        return clear

    def to_map_frame(self, x: ArrayLike, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Express world coordinates in the frame of the map's lower-left corner."""
        dx = np.asarray(x, dtype=float) - self._origin[0]
        dy = np.asarray(y, dtype=float) - self._origin[1]
        return (self._cos_yaw * dx + self._sin_yaw * dy,
                -self._sin_yaw * dx + self._cos_yaw * dy)

    def touches(self, x: ArrayLike, y: ArrayLike, radius: ArrayLike) -> np.ndarray:
        """
        Return a boolean array: does the circle at (x, y) touch an occupied cell or the outside.

        x, y and radius broadcast together; each radius must not exceed max_radius.
        """
        x, y, radius = np.broadcast_arrays(x, y, np.asarray(radius, dtype=float))
        shape = x.shape
        map_x, map_y, rows, cols, inside = self._cells(x.ravel(), y.ravel())
        radius = radius.ravel()
        result = ~inside
        candidates = np.flatnonzero(inside)
        candidates = candidates[self._near_obstacle[rows[candidates], cols[candidates]]]
        # The exact test weighs every cell of a window around each point: points go in
        # batches, so memory stays bounded however many points and however large the window.
        batch = max(1, CELLS_PER_BATCH // self._window_rows.size)
        for start in range(0, candidates.size, batch):
            chosen = candidates[start:start + batch]
            result[chosen] = self._touches_exactly(map_x[chosen], map_y[chosen], rows[chosen],
                                                   cols[chosen], radius[chosen])
        return result.reshape(shape)

    def _touches_exactly(self, map_x, map_y, rows, cols, radius):
        cell_rows = rows[:, None] + self._window_rows[None, :]
        cell_cols = cols[:, None] + self._window_cols[None, :]
        occupied = self._padded[cell_rows + self._pad, cell_cols + self._pad]
        half = 0.5 * self.resolution
        centre_x = (cell_cols + 0.5) * self.resolution
        centre_y = (cell_rows + 0.5) * self.resolution
        gap_x = np.maximum(np.abs(map_x[:, None] - centre_x) - half, 0.0)
        gap_y = np.maximum(np.abs(map_y[:, None] - centre_y) - half, 0.0)
        close = gap_x ** 2 + gap_y ** 2 < (radius ** 2)[:, None]
        return np.any(occupied & close, axis=1)
