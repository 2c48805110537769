"""
What a coursework's task adds to a course's tick-off sheet: its judge, on the run. No ROS here.

The lab's checks (verdicts.py) judge the statuses against the true path for every task; a
coursework's own rule is its judge's (courseworks/), given the course's world as the simulator
loaded it (the course's map and robot, the bundled ones where it names none) and the truth.
"""

from dataclasses import dataclass
import math

from courseworks.courses import submitted_map_topic
from courseworks.exploration import judge_exploration, reachable_free
from courseworks.grids import Grid
from courseworks.mapping import (AGREED, BEYOND_SIGHT, FALSE_WALL, judge_map, map_readings,
                                 MISSED_WALL, NOT_SAID, NOT_SEEN, on_world_cells,
                                 seen_along_run, WALL_SLACK_CELLS, WRONG)
from courseworks.names import EXPLORATION, MAPPING, PLANNING
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


# What a picture of the judge's reading shows: (code, label, colour) per code.
MAP_MEANINGS = ((NOT_SEEN, 'not seen', '#d9d9d9'), (AGREED, 'agreed', '#4daf4a'),
                (WRONG, 'said wrong', '#ff7f00'), (FALSE_WALL, 'false wall', '#e41a1c'),
                (MISSED_WALL, 'missed wall', '#377eb8'),
                (BEYOND_SIGHT, 'known beyond sight', '#984ea3'),
                (NOT_SAID, 'seen, not said', '#ffff99'))
UNREACHABLE_SPACE, SEEN_REACHABLE, UNSEEN_REACHABLE = 0, 1, 2
EXPLORATION_MEANINGS = ((UNREACHABLE_SPACE, 'walls, or out of reach', '#d9d9d9'),
                        (SEEN_REACHABLE, 'reachable, seen', '#4daf4a'),
                        (UNSEEN_REACHABLE, 'reachable, never seen', '#ff7f00'))


@dataclass(frozen=True)
class TaskPicture:
    """
    The world's cells as a coursework's judge read them: a code each, and what codes mean.

    submitted is the map judged (mapping), drawn beside the reading as it was published.
    """

    world: OccupancyMap
    codes: np.ndarray
    meanings: tuple[tuple[int, str, str], ...]
    title: str
    submitted: OccupancyMap | None = None


def judge_task(course: Course, run: Run, submitted_map: OccupancyMap | str | None = None
               ) -> tuple[list[Check], TaskPicture | None]:
    """
    Return the checks course's task adds to the lab's, and the picture of its judge's reading.

    The lab's own task adds none; planning has no picture. submitted_map is a mapping
    submission's last map, or the line saying why it was none.
    """
    if course.task == PLANNING:
        return [planning_check(course, run)], None
    if course.task == MAPPING:
        check, picture = mapping_check(course, run, submitted_map)
        return [check], picture
    if course.task == EXPLORATION:
        check, picture = exploration_check(course, run)
        return [check], picture
    return [], None


def _seen(course, run, grid):
    """Return what the course's robot's first laser could have seen along the true path."""
    laser = load_robot(robot_file(course.robot_file)).lasers[0]
    return seen_along_run(grid, run.poses, run.step, laser)


def exploration_check(course: Course, run: Run) -> tuple[Check, TaskPicture | None]:
    """Judge the reachable free space the laser saw along the true path, against the reference."""
    world = load_map(map_file(course.map_file))
    grid = Grid.from_map(world)
    if not load_robot(robot_file(course.robot_file)).lasers:
        return Check(EXPLORATION, False, f"the course's robot {robot_file(course.robot_file)} "
                     'has no laser to explore with'), None
    thresholds = task_thresholds(EXPLORATION, course.thresholds)
    reachable, sight = reachable_free(grid, course.start[:2]), _seen(course, run, grid)
    judgement = judge_exploration(reachable, sight, thresholds.reference_coverage, thresholds)
    codes = np.where(reachable, np.where(sight.seen_free, SEEN_REACHABLE, UNSEEN_REACHABLE),
                     UNREACHABLE_SPACE).astype(np.int8)
    picture = TaskPicture(world, codes, EXPLORATION_MEANINGS,
                          f'{course.name}: the reachable free space the laser saw')
    if not judgement.passed:
        return Check(EXPLORATION, False, '; '.join(judgement.failures)), picture
    return Check(EXPLORATION, True, f'saw {judgement.coverage:.1%} of the reachable free space '
                 f"(the reference explorer's {judgement.reference:.1%})"), picture


def mapping_check(course: Course, run: Run, submitted: OccupancyMap | str | None
                  ) -> tuple[Check, TaskPicture | None]:
    """
    Judge the last map a mapping submission published, over what its laser could have seen.

    The laser is the course's robot's first, cast from the true pose at the laser's rate.
    """
    if submitted is None:
        return Check(MAPPING, False, f'no map on {submitted_map_topic(course)} during the '
                     'run'), None
    if isinstance(submitted, str):
        return Check(MAPPING, False, f'the last map was no map: {submitted}'), None
    world = load_map(map_file(course.map_file))
    grid = Grid.from_map(world)
    if not math.isclose(submitted.origin[2], 0.0, abs_tol=1e-6):
        return Check(MAPPING, False, f'the map is turned by {submitted.origin[2]:g} rad from '
                     f'{_corner(submitted.origin)}: a map along x is judged (origin yaw 0)'), None
    cells = on_world_cells(submitted.cells, submitted.resolution, submitted.origin,
                           world.cells.shape, world.resolution, world.origin)
    # A coarser map's walls are judged with one of its cells of slack (a message's resolution
    # is a float32: a hair above the world's is the world's).
    slack = max(WALL_SLACK_CELLS, math.ceil(submitted.resolution / world.resolution - 1e-4))
    robot = load_robot(robot_file(course.robot_file))
    if not robot.lasers:
        return Check(MAPPING, False, f"the course's robot {robot_file(course.robot_file)} "
                     'has no laser to map with'), None
    sight = _seen(course, run, grid)
    judgement = judge_map(sight, cells, task_thresholds(MAPPING, course.thresholds), slack)
    picture = TaskPicture(world, map_readings(sight, cells, slack), MAP_MEANINGS,
                          f"{course.name}: the last map, as the judge read it on the world's "
                          'cells', submitted)
    figures = (f'agreement {judgement.agreement:.1%}, coverage {judgement.coverage:.1%}, false '
               f'walls {judgement.false_walls:.1%}, missed walls {judgement.missed_walls:.1%}, '
               f'known beyond sight {judgement.unseen:.1%}')
    if not judgement.passed:
        return Check(MAPPING, False, f'{"; ".join(judgement.failures)} ({figures})'), picture
    return Check(MAPPING, True, figures), picture


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
