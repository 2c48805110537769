"""
Exact footprint-versus-grid checks for circular and polygonal robots.

A circle touches an occupied cell when its centre is closer than its radius to the cell's
square; a polygon, when one of its edges enters the square or the square's centre lies inside
it (touching along an edge or at a corner is no overlap, as for circles). A distance
transform, done once, gives every cell a lower bound of the distance from any of its points to
an occupied square, so a robot in open space (or a step whose whole path stays in open space)
costs one lookup, and only robots near a wall pay for the exact check against the cells around
them: for a polygon, those within its circumradius, whatever its heading. Everything outside
the map counts as occupied. A circle's checks are compiled (numba), one circle at a time, so
the Bodies' compiled step calls them too; a polygon's, rarer, are numpy's.
"""

import math

from numba import njit
import numpy as np
from numpy.typing import ArrayLike
from scipy.ndimage import distance_transform_edt
from simple_robot_control.occupancy_map import OccupancyMap

CELLS_PER_BATCH = 1 << 22
# Rounding allowance on the wall-gap bound, metres: far below anything the bound decides.
GAP_SLACK = 1e-9


def wall_distances(occupied: np.ndarray) -> np.ndarray:
    """
    Return, per cell, the distance in cells from its centre to the nearest occupied one's.

    The map's outside counts as occupied: a ring of occupied cells around it is taken into
    account. This distance transform is the costly part of a map (a second for 16 M cells):
    the footprint checker and the range finder share one.
    """
    return distance_transform_edt(np.pad(~occupied, 1, constant_values=False))[1:-1, 1:-1]


class FootprintChecker:
    """Answers whether circles at given positions touch an occupied cell or leave the map."""

    def __init__(self, occupancy_map: OccupancyMap, max_radius: float,
                 distances: np.ndarray | None = None):
        """Prepare the checks; distances are the map's wall_distances, if already known."""
        if max_radius <= 0.0:
            raise ValueError(f'robot radius must be positive, got {max_radius}')
        self.resolution = occupancy_map.resolution
        self.max_radius = float(max_radius)
        origin_x, origin_y, yaw = occupancy_map.origin
        self._origin = (float(origin_x), float(origin_y))
        self._yaw = float(yaw)
        self._cos_yaw, self._sin_yaw = math.cos(yaw), math.sin(yaw)
        self._height, self._width = occupancy_map.occupied.shape
        self._pad = math.ceil(self.max_radius / self.resolution)
        self._padded = np.pad(occupancy_map.occupied, self._pad, constant_values=True)
        if distances is None:
            distances = wall_distances(occupancy_map.occupied)
        # From a point of a cell to the nearest occupied square is at least the distance
        # between the two cells' centres less a cell's diagonal (the map edge included).
        # In place, term by term: a map of 16 M cells holds several such arrays at once.
        self.wall_gap = distances - math.sqrt(2.0)
        self.wall_gap *= self.resolution
        self.wall_gap -= GAP_SLACK
        # The cells around a point's cell, nearest first, with the least gap between the
        # point's cell and each: a circle of radius r can touch only those whose gap is < r.
        steps = np.arange(-self._pad, self._pad + 1)
        rows, cols = (grid.ravel() for grid in np.meshgrid(steps, steps, indexing='ij'))
        gaps = self.resolution * np.hypot(np.maximum(np.abs(rows) - 1, 0),
                                          np.maximum(np.abs(cols) - 1, 0))
        order = np.argsort(gaps, kind='stable')
        self._window_rows, self._window_cols = rows[order], cols[order]
        self._window_gaps = gaps[order]

    @property
    def grid(self) -> tuple:
        """
        Return what the compiled checks read of the map, in circle_touches' order.

        Compiled functions called from Python take it as separate arguments (*grid): numba
        types a tuple argument in Python on every call, tens of microseconds.
        """
        return (self._origin[0], self._origin[1], self._cos_yaw, self._sin_yaw, self.resolution,
                self.wall_gap, self._padded, self._pad, self._window_rows, self._window_cols,
                self._window_gaps)

    def _cells(self, x, y):
        map_x, map_y = self.to_map_frame(x, y)
        cols = np.floor(map_x / self.resolution).astype(np.int64)
        rows = np.floor(map_y / self.resolution).astype(np.int64)
        inside = (rows >= 0) & (rows < self._height) & (cols >= 0) & (cols < self._width)
        return map_x, map_y, rows, cols, inside

    def clear_for_motion(self, x: ArrayLike, y: ArrayLike, step_length: ArrayLike,
                         radius: ArrayLike) -> np.ndarray:
        """
        Whether a circle of radius starting at (x, y) surely touches nothing on a path.

        The path may go anywhere within step_length of its start. False means it must be
        checked, not that it touches.
        """
        x, y, reach = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float),
                                          np.asarray(step_length, dtype=float) + radius)
        return _each_point(x.ravel(), y.ravel(), reach.ravel(), False,
                           *self.grid).reshape(x.shape)

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
        x, y, radius = np.broadcast_arrays(np.asarray(x, dtype=float),
                                           np.asarray(y, dtype=float),
                                           np.asarray(radius, dtype=float))
        return _each_point(x.ravel(), y.ravel(), radius.ravel(), True,
                           *self.grid).reshape(x.shape)

    def polygon_touches(self, x: ArrayLike, y: ArrayLike, theta: ArrayLike,
                        points: np.ndarray) -> np.ndarray:
        """
        Return, per pose, whether the polygon there overlaps an occupied cell or the outside.

        x, y and theta broadcast to one pose each; points are the polygon's corners in the
        body's frame, within max_radius of its centre.
        """
        x, y, theta = (np.ravel(value) for value in np.broadcast_arrays(
            np.asarray(x, dtype=float), np.asarray(y, dtype=float),
            np.asarray(theta, dtype=float)))
        corners = np.asarray(points, dtype=float)
        reach = float(np.max(np.hypot(corners[:, 0], corners[:, 1])))
        map_x, map_y, rows, cols, inside = self._cells(x, y)
        result = ~inside
        candidates = np.flatnonzero(inside)
        candidates = candidates[self.wall_gap[rows[candidates], cols[candidates]] < reach]
        if candidates.size == 0:
            return result
        window = int(np.searchsorted(self._window_gaps, reach))
        batch = max(1, CELLS_PER_BATCH // (window * len(corners)))
        for start in range(0, candidates.size, batch):
            chosen = candidates[start:start + batch]
            result[chosen] = self._polygon_touches_exactly(
                map_x[chosen], map_y[chosen], theta[chosen] - self._yaw, rows[chosen],
                cols[chosen], corners, window)
        return result

    def _polygon_touches_exactly(self, map_x, map_y, heading, rows, cols, corners, window):
        """Weigh each occupied cell in reach against the polygon, in the map's frame."""
        cell_rows = rows[:, None] + self._window_rows[None, :window]
        cell_cols = cols[:, None] + self._window_cols[None, :window]
        pose, cell = np.nonzero(self._padded[cell_rows + self._pad, cell_cols + self._pad])
        touched = np.zeros(map_x.size, dtype=bool)
        if pose.size == 0:
            return touched
        cos_heading, sin_heading = np.cos(heading)[:, None], np.sin(heading)[:, None]
        corner_x = map_x[:, None] + cos_heading * corners[:, 0] - sin_heading * corners[:, 1]
        corner_y = map_y[:, None] + sin_heading * corners[:, 0] + cos_heading * corners[:, 1]
        start_x, start_y = corner_x[pose], corner_y[pose]
        end_x, end_y = np.roll(start_x, -1, axis=1), np.roll(start_y, -1, axis=1)
        left = (cell_cols[pose, cell] * self.resolution)[:, None] + GAP_SLACK
        bottom = (cell_rows[pose, cell] * self.resolution)[:, None] + GAP_SLACK
        right = left + (self.resolution - 2.0 * GAP_SLACK)
        top = bottom + (self.resolution - 2.0 * GAP_SLACK)
        enters = np.any(segments_enter_boxes(start_x, start_y, end_x, end_y, left, right,
                                             bottom, top), axis=1)
        centre_inside = inside_polygons(0.5 * (left + right)[:, 0], 0.5 * (bottom + top)[:, 0],
                                        start_x, start_y, end_x, end_y)
        touched[pose[enters | centre_inside]] = True
        return touched


def segments_enter_boxes(start_x: np.ndarray, start_y: np.ndarray, end_x: np.ndarray,
                         end_y: np.ndarray, left: ArrayLike, right: ArrayLike, bottom: ArrayLike,
                         top: ArrayLike) -> np.ndarray:
    """
    Return whether each segment has points strictly inside its axis-aligned box.

    Liang and Barsky's clipping: the part of the segment within both slabs of the box is
    non-empty. Every argument broadcasts against the others.
    """
    enter = np.zeros(np.broadcast(start_x, left).shape)
    leave = np.ones_like(enter)
    for start, end, low, high in ((start_x, end_x, left, right), (start_y, end_y, bottom, top)):
        delta = end - start
        flat = delta == 0.0
        within = (start > low) & (start < high)
        with np.errstate(divide='ignore', invalid='ignore'):
            at_low, at_high = (low - start) / delta, (high - start) / delta
        enter = np.maximum(enter, np.where(flat, np.where(within, -np.inf, np.inf),
                                           np.minimum(at_low, at_high)))
        leave = np.minimum(leave, np.where(flat, np.where(within, np.inf, -np.inf),
                                           np.maximum(at_low, at_high)))
    return enter < leave


def inside_polygons(x: np.ndarray, y: np.ndarray, start_x: np.ndarray, start_y: np.ndarray,
                    end_x: np.ndarray, end_y: np.ndarray) -> np.ndarray:
    """
    Return whether each point (x[i], y[i]) lies inside polygon i, given by its edges' ends.

    The even-odd rule: a ray from the point crosses the polygon's edges an odd number of
    times.
    """
    x, y = x[:, None], y[:, None]
    straddles = (start_y > y) != (end_y > y)
    with np.errstate(divide='ignore', invalid='ignore'):
        crossing_x = start_x + (y - start_y) * (end_x - start_x) / (end_y - start_y)
    return np.count_nonzero(straddles & (x < crossing_x), axis=1) % 2 == 1


@njit(cache=True)
def _map_cell(grid, x, y):
    """Return (map x, map y, row, column, whether the cell is on the map) of a point."""
    origin_x, origin_y, cos_yaw, sin_yaw, resolution, wall_gap = grid[:6]
    dx, dy = x - origin_x, y - origin_y
    map_x, map_y = cos_yaw * dx + sin_yaw * dy, -sin_yaw * dx + cos_yaw * dy
    col, row = math.floor(map_x / resolution), math.floor(map_y / resolution)
    height, width = wall_gap.shape
    return map_x, map_y, row, col, 0 <= row < height and 0 <= col < width


@njit(cache=True)
def clear_at(grid: tuple, x: float, y: float, reach: float) -> bool:
    """Whether nothing occupied lies within reach of any point of (x, y)'s cell (a bound)."""
    _, _, row, col, inside = _map_cell(grid, x, y)
    return inside and grid[5][row, col] >= reach


@njit(cache=True)
def circle_touches(grid: tuple, x: float, y: float, radius: float) -> bool:
    """
    Whether a circle touches an occupied cell or the outside: the exact check of one circle.

    grid is FootprintChecker.grid. In open space the wall gap answers at once; near a wall the
    cells around the circle's, nearest first, are weighed as far out as the radius reaches.
    """
    map_x, map_y, row, col, inside = _map_cell(grid, x, y)
    if not inside:
        return True
    resolution, wall_gap, padded, pad, window_rows, window_cols, window_gaps = grid[4:]
    if wall_gap[row, col] >= radius:
        return False
    half = 0.5 * resolution
    for cell in range(window_gaps.size):
        if window_gaps[cell] >= radius:
            break
        cell_row, cell_col = row + window_rows[cell], col + window_cols[cell]
        if not padded[cell_row + pad, cell_col + pad]:
            continue
        gap_x = max(abs(map_x - (cell_col + 0.5) * resolution) - half, 0.0)
        gap_y = max(abs(map_y - (cell_row + 0.5) * resolution) - half, 0.0)
        if gap_x * gap_x + gap_y * gap_y < radius * radius:
            return True
    return False


@njit(cache=True)
def _each_point(x, y, values, exact, *grid):
    """Return circle_touches (exact, values the radii) or clear_at (values the reaches) a point."""
    answers = np.empty(x.size, dtype=np.bool_)
    for point in range(x.size):
        answers[point] = (circle_touches(grid, x[point], y[point], values[point]) if exact
                          else clear_at(grid, x[point], y[point], values[point]))
    return answers
