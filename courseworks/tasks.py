"""
The tasks a course may ask, by name, and the thresholds each takes. No ROS here.

The lab's waypoints (waypoint_lab) and the courseworks that follow it: mapping, exploration,
planning. A course file names its task and may set any of that task's thresholds; each
threshold has a range with meaning (fractions from 0 to 1, a path ratio from 1).
"""

from dataclasses import fields, replace

from courseworks.names import EXPLORATION, MAPPING, PLANNING
from courseworks.thresholds import ExplorationThresholds, MapThresholds, PlanningThresholds
from simple_robot_control.validation import Bounds, describe
from waypoint_lab.rules import WAYPOINTS_TASK

# Each task's thresholds (None: the lab's task, graded by its own limits).
THRESHOLDS = {WAYPOINTS_TASK: None, MAPPING: MapThresholds, EXPLORATION: ExplorationThresholds,
              PLANNING: PlanningThresholds}
TASKS = tuple(THRESHOLDS)
_FRACTION = Bounds(0.0, 1.0)
_BOUNDS = {'max_path_ratio': Bounds(1.0, 100.0)}


class TaskError(ValueError):
    """A task or threshold that cannot be; the message is one line naming it."""


def check_task(task: object) -> str:
    """Return task if it is one a course may ask; TaskError names the known ones otherwise."""
    if task not in THRESHOLDS:
        raise TaskError(f'task must be one of {", ".join(TASKS)}, got {describe(task)}')
    return task


def thresholds_for(task: str, given: object) -> tuple[tuple[str, float], ...]:
    """Check a course's thresholds (a mapping of name to number) for task; return them as pairs."""
    kind = THRESHOLDS[check_task(task)]
    if given is None:
        return ()
    if not isinstance(given, dict):
        raise TaskError(f'thresholds must be a mapping of name to number, got {describe(given)}')
    names = [field.name for field in fields(kind)] if kind else []
    pairs = []
    for name, value in given.items():
        if name not in names:
            known = ', '.join(names) if names else 'none: the lab has its own limits'
            raise TaskError(f'the {task} task has no threshold {describe(name)} (known: {known})')
        problem = _BOUNDS.get(name, _FRACTION).problem(f'threshold {name}', value)
        if problem:
            raise TaskError(problem)
        pairs.append((name, float(value)))
    return tuple(pairs)


def task_thresholds(task: str, pairs: tuple[tuple[str, float], ...] = ()) -> object:
    """Return task's thresholds: its defaults with a course's pairs in place."""
    kind = THRESHOLDS[check_task(task)]
    if kind is None:
        raise TaskError(f'the {task} task has no thresholds of its own')
    return replace(kind(), **dict(pairs))
