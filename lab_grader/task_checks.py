"""
What a coursework's task adds to a course's tick-off sheet: its judge, on the run. No ROS here.

The lab's checks (verdicts.py) judge the statuses against the true path for every task; a
coursework's own rule is its judge's (courseworks/), given the course's world as the simulator
loaded it (the course's map and robot, the bundled ones where it names none) and the truth.
"""

import math

from courseworks.exploration import judge_exploration, reachable_free
from courseworks.grids import Grid
from courseworks.mapping import judge_map, seen_along_run
from courseworks.names import EXPLORATION, MAPPING, PLANNING, SUBMITTED_MAP_TOPIC
from courseworks.planning import clearance_along, judge_planning, plan_legs
from courseworks.tasks import task_thresholds
from lab_grader.verdicts import Check
import numpy as np
from simple_robot_control.occupancy_map import load_map, OccupancyMap
from stdr_lite.core.loading import map_file, robot_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.course import Course
from waypoint_lab.run import Run
from waypoint_lab.status import UNREACHABLE, WAYPOINT


def task_checks(course: Course, run: Run,
                submitted_map: OccupancyMap | str | None = None) -> list[Check]:
    """
    Return the checks course's task adds to the lab's (none for the lab's own task).

    submitted_map is a mapping submission's last map, or the line saying why it was none.
    """
    if course.task == PLANNING:
        return [planning_check(course, run)]
    if course.task == MAPPING:
        return [mapping_check(course, run, submitted_map)]
    if course.task == EXPLORATION:
        return [exploration_check(course, run)]
    return []


def _seen(course, run, grid):
    """Return what the course's robot's first laser could have seen along the true path."""
    laser = load_robot(robot_file(course.robot_file)).lasers[0]
    return seen_along_run(grid, run.poses, run.step, laser)


def exploration_check(course: Course, run: Run) -> Check:
    """Judge the reachable free space the laser saw along the true path, against the reference."""
    grid = Grid.from_map(load_map(map_file(course.map_file)))
    if not load_robot(robot_file(course.robot_file)).lasers:
        return Check(EXPLORATION, False, f"the course's robot {robot_file(course.robot_file)} "
                     'has no laser to explore with')
    thresholds = task_thresholds(EXPLORATION, course.thresholds)
    judgement = judge_exploration(reachable_free(grid, course.start[:2]),
                                  _seen(course, run, grid), thresholds.reference_coverage,
                                  thresholds)
    if not judgement.passed:
        return Check(EXPLORATION, False, '; '.join(judgement.failures))
    return Check(EXPLORATION, True, f'saw {judgement.coverage:.1%} of the reachable free space '
                 f"(the reference explorer's {judgement.reference:.1%})")


def mapping_check(course: Course, run: Run, submitted: OccupancyMap | str | None) -> Check:
    """
    Judge the last map a mapping submission published, over what its laser could have seen.

    The laser is the course's robot's first, cast from the true pose at the laser's rate.
    """
    if submitted is None:
        return Check(MAPPING, False, f'no map on {SUBMITTED_MAP_TOPIC} during the run')
    if isinstance(submitted, str):
        return Check(MAPPING, False, f'the last map was no map: {submitted}')
    world = load_map(map_file(course.map_file))
    grid = Grid.from_map(world)
    if (submitted.cells.shape != world.cells.shape
            # A message's resolution is a float32.
            or not math.isclose(submitted.resolution, world.resolution, rel_tol=1e-6)
            or not all(math.isclose(a, b, abs_tol=world.resolution / 2)
                       for a, b in zip(submitted.origin, world.origin))):
        return Check(MAPPING, False, f'the map is {submitted.width}x{submitted.height} cells '
                     f'of {submitted.resolution:g} m from {_corner(submitted.origin)}; the '
                     f'world is {world.width}x{world.height} of {world.resolution:g} m from '
                     f'{_corner(world.origin)} (/map_metadata gives it)')
    robot = load_robot(robot_file(course.robot_file))
    if not robot.lasers:
        return Check(MAPPING, False, f"the course's robot {robot_file(course.robot_file)} "
                     'has no laser to map with')
    judgement = judge_map(_seen(course, run, grid), submitted.cells,
                          task_thresholds(MAPPING, course.thresholds))
    figures = (f'agreement {judgement.agreement:.1%}, coverage {judgement.coverage:.1%}, false '
               f'walls {judgement.false_walls:.1%}, missed walls {judgement.missed_walls:.1%}, '
               f'known beyond sight {judgement.unseen:.1%}')
    if not judgement.passed:
        return Check(MAPPING, False, f'{"; ".join(judgement.failures)} ({figures})')
    return Check(MAPPING, True, figures)


def _corner(origin):
    return f'({origin[0]:g}, {origin[1]:g})'


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
