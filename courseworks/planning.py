"""
The planning coursework's judge: short paths clear of walls, unreachable goals said so.

Goals reached in order by short paths that keep off the walls, and goals no robot can reach
said to be unreachable. No ROS here.

Whether a goal was reached is the lab's rule (the goal set of d and t, judged from the true
path by the lab's judge); this module adds what planning asks. The judge plans for itself: a
goal is reachable when its cell lies in the start's free region of the map inflated by the
robot's radius, and each leg's optimum is the shortest 8-connected path there (grids.py) from
the last goal reached. A leg's path is the robot's true path between the two goals.
"""

from dataclasses import dataclass
import math

from courseworks.grids import Grid, inflate, path_lengths
from courseworks.judgement import Judgement
from courseworks.thresholds import PlanningThresholds
import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage


@dataclass(frozen=True)
class Leg:
    """One goal's figures: reachable by the judge, the optimum and driven lengths (m)."""

    goal: int
    reachable: bool
    optimum: float
    driven: float | None = None

    @property
    def ratio(self) -> float | None:
        if self.driven is None or not self.optimum:
            return None
        return self.driven / self.optimum


@dataclass(frozen=True)
class PlanningJudgement(Judgement):
    """The legs, the closest the robot came to a wall (m), and why it failed."""

    legs: tuple[Leg, ...]
    clearance: float
    failures: tuple[str, ...]


def plan_legs(grid: Grid, radius: float, start: tuple, goals: ArrayLike) -> list[Leg]:
    """Return each goal's leg: reachable or not, and its optimum from the goal before it."""
    free = ~inflate(grid, radius)
    here = grid.cell_of(start[0], start[1])
    # Every goal reached lies in the start's region: a goal is reachable when a path from the
    # last one reached (or the start) gets to it.
    lengths = (path_lengths(free, here, grid.resolution) if here is not None
               else np.full(grid.shape, np.inf))
    legs = []
    for number, (x, y, _) in enumerate(np.asarray(goals, dtype=float).reshape(-1, 3), start=1):
        cell = grid.cell_of(x, y)
        if cell is None or not np.isfinite(lengths[cell]):
            legs.append(Leg(number, False, math.inf))
            continue
        legs.append(Leg(number, True, float(lengths[cell])))
        lengths = path_lengths(free, cell, grid.resolution)
    return legs


def clearance_along(grid: Grid, positions: ArrayLike) -> tuple[float, tuple[float, float]]:
    """
    Return the least distance from the robot's centre to a wall along positions, and where.

    Measured from each position's cell centre to the nearest wall cell's edge (half a cell
    short of its centre), so it is within a cell of the true figure.
    """
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    if not len(positions):
        return math.inf, (math.nan, math.nan)
    distance = ndimage.distance_transform_edt(~grid.walls) * grid.resolution
    rows, columns = grid.shape
    column = np.floor((positions[:, 0] - grid.origin[0]) / grid.resolution).astype(int)
    row = np.floor((positions[:, 1] - grid.origin[1]) / grid.resolution).astype(int)
    on_map = (row >= 0) & (row < rows) & (column >= 0) & (column < columns)
    # Off the map counts as in a wall.
    clearance = np.where(on_map, distance[row.clip(0, rows - 1), column.clip(0, columns - 1)]
                         - 0.5 * grid.resolution, 0.0)
    least = int(np.argmin(clearance))
    return float(clearance[least]), (float(positions[least, 0]), float(positions[least, 1]))


def judge_planning(legs: list[Leg], path: ArrayLike, reached_at: dict[int, int],
                   said_unreachable: set[int], radius: float, clearance: float,
                   thresholds: PlanningThresholds = PlanningThresholds()) -> PlanningJudgement:
    """
    Judge a run of the planning task.

    path is the true path (x, y) in order; reached_at maps each goal the lab's
    judge found reached to its index in path; said_unreachable holds the goals the submission
    reported unreachable; clearance is clearance_along's figure for the path.
    """
    path = np.asarray(path, dtype=float).reshape(-1, 2)
    steps = np.sqrt(np.sum(np.diff(path, axis=0) ** 2, axis=1))
    travelled = np.concatenate(([0.0], np.cumsum(steps)))
    failures, judged, since = [], [], 0
    for leg in legs:
        if not leg.reachable:
            if leg.goal not in said_unreachable:
                failures.append(f'goal {leg.goal} is unreachable and was not reported so')
            judged.append(leg)
            continue
        if leg.goal in said_unreachable:
            failures.append(f'goal {leg.goal} was reported unreachable; the judge reaches it '
                            f'by {leg.optimum:.2f} m')
        if leg.goal not in reached_at:
            failures.append(f'goal {leg.goal} was not reached')
            judged.append(leg)
            continue
        index = reached_at[leg.goal]
        driven = float(travelled[index] - travelled[since])
        judged.append(Leg(leg.goal, True, leg.optimum, driven))
        since = index
        ratio = judged[-1].ratio
        if ratio is not None and ratio > thresholds.max_path_ratio:
            failures.append(f'goal {leg.goal}: drove {driven:.2f} m, {ratio:.2f}x the shortest '
                            f'{leg.optimum:.2f} m (at most {thresholds.max_path_ratio:g}x)')
    if clearance < radius:
        failures.append(f'touched a wall: the centre came within {max(clearance, 0.0):.2f} m '
                        f'of one (radius {radius:g} m)')
    return PlanningJudgement(tuple(judged), clearance, tuple(failures))
