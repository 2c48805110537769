"""The reference explorer's frontiers, and shortest paths cell by cell, on crafted grids."""

from coursework_answers.frontiers import frontier_cells, nearest_frontier
from courseworks.grids import shortest_path
import numpy as np
import pytest

UNKNOWN, FREE, WALL = -1, 0, 100


def half_known(rows=20, columns=40):
    """Return a grid whose left half is known free, walled round, and whose right is unknown."""
    cells = np.full((rows, columns), UNKNOWN, dtype=np.int8)
    cells[:, :20] = FREE
    cells[0, :20] = cells[-1, :20] = cells[:, 0] = WALL
    return cells


def test_frontiers_are_free_cells_beside_the_unknown_and_specks_are_not():
    cells = half_known()
    frontier = frontier_cells(cells)
    assert frontier[1:-1, 19].all() and not frontier[:, :19].any()
    cells[5, 5] = UNKNOWN
    assert not frontier_cells(cells)[5, 4]
    known = np.where(cells < 0, FREE, cells)
    assert not frontier_cells(known).any()


def test_the_explorer_goes_to_the_nearest_frontier_it_can_drive_to():
    cells = half_known()
    goal = nearest_frontier(cells, 0.1, (0.0, 0.0), (1.05, 1.05), 0.15)
    assert goal == pytest.approx((1.95, 1.05))
    # A wall across the way to the near end of the frontier: the far end is the nearest.
    cells[:10, 10] = WALL
    cells[9, 10:20] = WALL
    goal = nearest_frontier(cells, 0.1, (0.0, 0.0), (0.55, 0.55), 0.15)
    assert goal[1] > 0.9
    cells[10:, 10] = WALL
    assert nearest_frontier(cells, 0.1, (0.0, 0.0), (0.55, 0.55), 0.15) is None
    assert nearest_frontier(cells, 0.1, (0.0, 0.0), (-1.0, 0.55), 0.15) is None


def test_a_shortest_path_goes_round_a_wall_cell_by_cell():
    free = np.ones((5, 5), dtype=bool)
    free[1:4, 2] = False
    path = shortest_path(free, (2, 0), (2, 4), 0.1)
    assert path[0] == (2, 0) and path[-1] == (2, 4)
    assert all(free[cell] for cell in path)
    assert all(max(abs(a - c), abs(b - d)) == 1 for (a, b), (c, d) in zip(path, path[1:]))
    free[:, 2] = False
    assert shortest_path(free, (2, 0), (2, 4), 0.1) == []
