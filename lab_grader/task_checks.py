"""
What a coursework's task adds to a course's tick-off sheet: its judge, on the run. No ROS here.

The lab's checks (verdicts.py) judge the statuses against the true path for every task; a
coursework's own rule is its judge's (courseworks/), given the course's world as the simulator
loaded it (the course's map and robot, the bundled ones where it names none) and the truth.
"""

from courseworks.grids import Grid
from courseworks.planning import clearance_along, judge_planning, plan_legs
from courseworks.tasks import PLANNING, task_thresholds
from lab_grader.verdicts import Check
import numpy as np
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.loading import map_file, robot_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.course import Course
from waypoint_lab.rules import WAYPOINTS_TASK
from waypoint_lab.run import Run
from waypoint_lab.status import UNREACHABLE, WAYPOINT

# The tasks grade_lab runs: the lab's, and the courseworks' whose run it knows how to judge.
GRADED_TASKS = (WAYPOINTS_TASK, PLANNING)


def task_checks(course: Course, run: Run) -> list[Check]:
    """Return the checks course's task adds to the lab's (none for the lab's own task)."""
    if course.task == PLANNING:
        return [planning_check(course, run)]
    return []


def planning_check(course: Course, run: Run) -> Check:
    """
    Judge a planning run: short legs, clear of walls, unreachable goals said so.

    A goal counts as reached where its WAYPOINT report passed the lab's check; its leg ends at
    the true pose of the report's date.
    """
    grid = Grid.from_map(load_map(map_file(course.map_file)))
    radius = load_robot(robot_file(course.robot_file)).radius
    goals = [(waypoint.x, waypoint.y, waypoint.theta) for waypoint in course.waypoints]
    legs = plan_legs(grid, radius, course.start, goals)
    reached_at, said_unreachable = {}, set()
    last = len(run.times) - 1
    for report in run.statuses:
        status = report.status
        if status.kind == WAYPOINT and status.number not in reached_at:
            index = int(np.searchsorted(run.times, report.time, side='right')) - 1
            reached_at[status.number] = min(max(index, 0), last)
        elif status.kind == UNREACHABLE:
            said_unreachable.add(status.number)
    path = run.poses[:, :2]
    clearance, _ = clearance_along(grid, path)
    judgement = judge_planning(legs, path, reached_at, said_unreachable, radius, clearance,
                               task_thresholds(PLANNING, course.thresholds))
    if not judgement.passed:
        return Check(PLANNING, False, '; '.join(judgement.failures))
    driven = ', '.join(f'goal {leg.goal} {leg.driven:.2f} m ({leg.ratio:.2f}x the shortest)'
                       for leg in judgement.legs if leg.ratio is not None)
    given_up = [str(leg.goal) for leg in judgement.legs if not leg.reachable]
    unreachable = f'; unreachable goal(s) {", ".join(given_up)} reported so' if given_up else ''
    return Check(PLANNING, True, f'{driven or "no leg driven"}{unreachable}; the centre kept '
                 f'{judgement.clearance:.2f} m from walls (radius {radius:g} m)')
