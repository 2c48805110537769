"""
The grid a coursework is judged on: cells and metres, walls grown, free space, shortest paths.

Walls are grown by the robot's radius; free space is what a robot can reach; paths are the
shortest collision-free ones. No ROS here.

Cells are indexed (row, column) as nav_msgs/OccupancyGrid lays them out: row 0 at the map's
origin, rows along y. Distances and search come from scipy (the Euclidean distance transform,
connected components, Dijkstra on the 8-connected grid), never from code of our own.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from simple_robot_control.occupancy_map import OccupancyMap

# How a grid's values read, as map_server reads nav_msgs/OccupancyGrid's: occupied from 65, free
# up to 25, unknown otherwise (-1, or in between).
OCCUPIED_FROM = 65
FREE_UP_TO = 25
# 8-connected moves (row, column), each with its length in cells.
_MOVES = ((0, 1, 1.0), (1, 0, 1.0), (1, 1, math.sqrt(2.0)), (1, -1, math.sqrt(2.0)))
_EIGHT_CONNECTED = np.ones((3, 3), dtype=bool)


class GridError(ValueError):
    """A map no coursework can be judged on; the message is one line naming it."""


@dataclass(frozen=True)
class Grid:
    """A map's walls and geometry: walls[row, column] True where the robot may not be."""

    walls: np.ndarray
    resolution: float
    origin: tuple[float, float]

    @classmethod
    def from_map(cls, occupancy_map: OccupancyMap, unknown_is_wall: bool = True) -> 'Grid':
        """
        Take a map's walls; unknown cells count as walls unless unknown_is_wall is False.

        A judge sends no robot into the unknown; a planner on a map still being built tries it.
        """
        if occupancy_map.origin[2] != 0.0:
            raise GridError(f'{occupancy_map.source}: a rotated map (origin yaw '
                            f'{occupancy_map.origin[2]:g}); the courseworks take maps along x')
        walls, free = read_cells(occupancy_map.cells)
        if unknown_is_wall:
            walls |= ~free
        return cls(walls, occupancy_map.resolution, tuple(occupancy_map.origin[:2]))

    @property
    def shape(self) -> tuple[int, int]:
        return self.walls.shape

    def cell_of(self, x: float, y: float) -> tuple[int, int] | None:
        """Return the (row, column) holding the point (x, y), None off the map."""
        column = math.floor((x - self.origin[0]) / self.resolution)
        row = math.floor((y - self.origin[1]) / self.resolution)
        rows, columns = self.shape
        return (row, column) if 0 <= row < rows and 0 <= column < columns else None

    def within(self, point: tuple[float, float], distance: float) -> np.ndarray:
        """Return the cells whose centres lie within distance of point."""
        rows, columns = np.indices(self.shape)
        return np.hypot(self.origin[0] + (columns + 0.5) * self.resolution - point[0],
                        self.origin[1] + (rows + 0.5) * self.resolution - point[1]) <= distance

    def centre_of(self, row: int, column: int) -> tuple[float, float]:
        """Return the point at the centre of a cell."""
        return (self.origin[0] + (column + 0.5) * self.resolution,
                self.origin[1] + (row + 0.5) * self.resolution)


def read_cells(cells: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Return (walls, free) of a grid's values (-1 unknown, 0 to 100 occupancy)."""
    cells = np.asarray(cells)
    return cells >= OCCUPIED_FROM, (cells >= 0) & (cells <= FREE_UP_TO)


def inflate(grid: Grid, radius: float) -> np.ndarray:
    """
    Return the cells a disc of radius may not have its centre in: within radius of a wall.

    Measured from cell centre to cell centre, so a robot centred in a free cell of the result
    keeps at least radius minus half a cell from every wall.
    """
    distance = ndimage.distance_transform_edt(~grid.walls) * grid.resolution
    return grid.walls | (distance <= radius)


def region_of(free: np.ndarray, cell: tuple[int, int]) -> np.ndarray:
    """Return the free cells 8-connected to cell (empty if cell is not free)."""
    if not free[cell]:
        return np.zeros_like(free)
    labels, _ = ndimage.label(free, structure=_EIGHT_CONNECTED)
    return labels == labels[cell]


def path_lengths(free: np.ndarray, start: tuple[int, int], resolution: float) -> np.ndarray:
    """
    Return the length in metres of the shortest 8-connected path from start to each cell.

    A diagonal move needs both cells beside it free (no corner is cut); cells not reached, and
    every cell when start is not free, are inf. The path along cell centres is at most 8% longer
    than the straight-line shortest path (a move of 22.5 degrees costs 1.08 times its length).
    """
    return _search(free, start, resolution)[0]


def shortest_path(free: np.ndarray, start: tuple[int, int], goal: tuple[int, int],
                  resolution: float, cost: np.ndarray | None = None) -> list[tuple[int, int]]:
    """
    Return the cells of a shortest path from start to goal (as path_lengths), [] if none.

    cost, if given, weighs each cell (1 and up): a move costs its length times the mean of its
    two cells' costs, so the path keeps off costly cells where it can (a planner's margin).
    """
    lengths, previous = _search(free, start, resolution, cost)
    if not np.isfinite(lengths[goal]):
        return []
    columns = free.shape[1]
    cells, here = [], goal[0] * columns + goal[1]
    while here >= 0:
        cells.append(divmod(int(here), columns))
        here = previous[here]
    return cells[::-1]


def _search(free, start, resolution, cost=None):
    """Dijkstra from start over free's 8-connected graph: lengths, and each cell's previous."""
    rows, columns = free.shape
    if not free[start]:
        return np.full(free.shape, np.inf), np.full(rows * columns, -9999)
    index = np.arange(rows * columns).reshape(rows, columns)
    sources, targets, weights = [], [], []
    for row_step, column_step, length in _MOVES:
        row_from = slice(0, rows - row_step)
        row_to = slice(row_step, rows)
        column_from = slice(max(0, -column_step), columns - max(0, column_step))
        column_to = slice(max(0, column_step), columns + min(0, column_step))
        both = free[row_from, column_from] & free[row_to, column_to]
        if row_step and column_step:
            # The two cells the diagonal passes between.
            both &= free[row_to, column_from] & free[row_from, column_to]
        sources.append(index[row_from, column_from][both])
        targets.append(index[row_to, column_to][both])
        weight = np.full(int(both.sum()), length * resolution)
        if cost is not None:
            weight *= 0.5 * (cost[row_from, column_from][both] + cost[row_to, column_to][both])
        weights.append(weight)
    source, target = np.concatenate(sources), np.concatenate(targets)
    graph = coo_matrix((np.concatenate(weights), (source, target)),
                       shape=(rows * columns, rows * columns)).tocsr()
    lengths, previous = dijkstra(graph, directed=False, indices=int(index[start]),
                                 return_predecessors=True)
    return lengths.reshape(rows, columns), previous
