"""
The exploration coursework's judge: the reachable free space seen, against the reference's.

How much of the free space the robot can reach its laser saw within the time limit, against
the reference explorer's figure. No ROS here.

The reachable free space is every free cell of the world joined to the start's by free cells
(8-connected): the rooms the robot can enter or look into, not the store room behind a wall.
What was seen is what the laser could have seen along the true path (mapping.seen_along), so
an explorer is judged on where it drove, whatever its map says.
"""

from dataclasses import dataclass

from courseworks.grids import Grid, region_of
from courseworks.judgement import Judgement
from courseworks.mapping import Sight
from courseworks.thresholds import ExplorationThresholds
import numpy as np


@dataclass(frozen=True)
class ExplorationJudgement(Judgement):
    """The fraction of the reachable free space seen, the reference's, and why it failed."""

    coverage: float
    reference: float
    failures: tuple[str, ...]


def reachable_free(grid: Grid, start: tuple[float, float]) -> np.ndarray:
    """Return the free cells joined to the start's (none when the start is off the map)."""
    cell = grid.cell_of(*start)
    if cell is None:
        return np.zeros(grid.shape, dtype=bool)
    return region_of(~grid.walls, cell)


def judge_exploration(reachable: np.ndarray, sight: Sight, reference: float,
                      thresholds: ExplorationThresholds = ExplorationThresholds()
                      ) -> ExplorationJudgement:
    """Judge the seen share of reachable against the reference explorer's share (0 to 1)."""
    total = int(np.count_nonzero(reachable))
    coverage = float(np.count_nonzero(reachable & sight.seen_free)) / total if total else 0.0
    failures = []
    needed = max(thresholds.min_coverage, thresholds.of_reference * reference)
    if coverage < needed:
        failures.append(f'saw {coverage:.1%} of the reachable free space, needs {needed:.1%} '
                        f"({thresholds.of_reference:.0%} of the reference explorer's "
                        f'{reference:.1%})')
    return ExplorationJudgement(coverage, reference, tuple(failures))
