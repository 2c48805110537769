"""
The reference explorer's choice: the nearest frontier it can drive to. No ROS here.

A frontier is a known free cell beside an unknown one (Yamauchi's frontier-based exploration);
frontier cells touching each other make one frontier, and frontiers of fewer than min_cells
are noise at the edge of a ray, not a way into the unknown. The explorer drives to the frontier
cell nearest by path on its own map, walls grown by the robot's radius (courseworks.grids).
"""

from courseworks.grids import Grid, inflate, path_lengths, read_cells
import numpy as np
from scipy import ndimage

MIN_FRONTIER_CELLS = 5
_FOUR_NEIGHBOURS = ndimage.generate_binary_structure(2, 1)
_EIGHT_NEIGHBOURS = np.ones((3, 3), dtype=bool)


def frontier_cells(cells: np.ndarray, min_cells: int = MIN_FRONTIER_CELLS) -> np.ndarray:
    """Return the cells of a grid (nav_msgs values) on frontiers of at least min_cells."""
    walls, free = read_cells(cells)
    # Unknown as map_server reads a grid: -1, or a value between its thresholds (seen once).
    unknown = ~(walls | free)
    beside_unknown = ndimage.binary_dilation(unknown, structure=_FOUR_NEIGHBOURS)
    frontier = free & beside_unknown
    labels, count = ndimage.label(frontier, structure=_EIGHT_NEIGHBOURS)
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    sizes[0] = 0
    return sizes[labels] >= min_cells


def nearest_frontier(cells: np.ndarray, resolution: float, origin: tuple[float, float],
                     position: tuple[float, float], radius: float,
                     excluded: np.ndarray | None = None) -> tuple[float, float] | None:
    """
    Return the centre of the frontier cell nearest position by a drivable path, None if none.

    Drivable: through cells the map knows free, walls grown by radius; the robot's own cell
    counts as free (it stands there). Cells of excluded (given up) are no targets.
    """
    walls, free = read_cells(cells)
    grid = Grid(walls, resolution, origin)
    here = grid.cell_of(*position)
    if here is None:
        return None
    drivable = free & ~inflate(grid, radius)
    drivable[here] = True
    lengths = path_lengths(drivable, here, resolution)
    targets = frontier_cells(cells) & np.isfinite(lengths)
    if excluded is not None:
        targets &= ~excluded
    if not targets.any():
        return None
    row, column = np.unravel_index(np.argmin(np.where(targets, lengths, np.inf)), lengths.shape)
    return grid.centre_of(int(row), int(column))
