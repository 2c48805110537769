"""
The thresholds each coursework's judge takes: light, so a course file is read without the judges.

A course file may set any of its task's thresholds (tasks.py checks them); the judges
(mapping.py, exploration.py, planning.py) take them.
"""

from dataclasses import dataclass


@dataclass(frozen=True)
class MapThresholds:
    """What a map must reach over the seen cells (fractions, 0 to 1)."""

    min_agreement: float = 0.9
    max_false_walls: float = 0.05
    max_missed_walls: float = 0.2
    min_coverage: float = 0.8
    max_unseen: float = 0.1


@dataclass(frozen=True)
class ExplorationThresholds:
    """
    min_coverage: the fraction to see; of_reference: the share of the reference's figure.

    reference_coverage is the reference explorer's figure on the scenario (bench/courseworks.py
    prints it), written in the scenario's file; without it, all the reachable free space.
    """

    min_coverage: float = 0.0
    of_reference: float = 0.8
    reference_coverage: float = 1.0


@dataclass(frozen=True)
class PlanningThresholds:
    """max_path_ratio: a leg's true length over the judge's optimum, at most."""

    max_path_ratio: float = 1.5
