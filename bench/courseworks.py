"""
The courseworks' reference answers on the bundled scenarios: their figures, as ratios.

Each scenario is run by the reference answers in the simulation core (coursework_answers/
reference_run.py: the same laws and mapper as the nodes, no ROS) and judged by the courseworks'
judges, which grade_lab uses. Printed per scenario:

- planning: the route's length over the judge's shortest (each goal's leg, summed), the least
  clearance over the robot's radius, the verdict;
- mapping: the judge's agreement, coverage, false and missed walls, and what the map knows
  beyond the laser's sight (all fractions), the verdict;
- exploration: the share of the reachable free space seen, and over the scenario's reference
  figure (a scenario's reference_coverage is this bench's coverage), and the share seen by
  each quarter of the run's sim time;
- both: sim time over the CPU time it took (how much faster than real time a run goes here).

--smoke runs the plus room's mapping and planning scenarios only (seconds), as make test does.
"""

import argparse
import sys

from coursework_answers.reference_run import ReferenceRun, run_reference
from courseworks.courses import find_courses
from courseworks.exploration import judge_exploration, reachable_free
from courseworks.grids import Grid
from courseworks.mapping import judge_map, seen_along_run
from courseworks.names import EXPLORATION, MAPPING
from courseworks.planning import clearance_along, judge_planning, plan_legs
from courseworks.tasks import task_thresholds
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import shared_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.status import UNREACHABLE, WAYPOINT

SMOKE = ('plus_room_mapping', 'plus_room_planning')


def planning_figures(course, run, grid, radius):
    """Return the planning judge's verdict and figures of a reference run."""
    legs = plan_legs(grid, radius, course.start, course.waypoints)
    reached = {status.number: step for step, status in run.statuses if status.kind == WAYPOINT}
    given_up = {status.number for _, status in run.statuses if status.kind == UNREACHABLE}
    path = run.poses[:, :2]
    clearance, _ = clearance_along(grid, path)
    judgement = judge_planning(legs, path, reached, given_up, radius, clearance,
                               task_thresholds(course.task, course.thresholds))
    driven = sum(leg.driven for leg in judgement.legs if leg.driven is not None)
    shortest = sum(leg.optimum for leg in judgement.legs if leg.driven is not None)
    return judgement, (f'path {driven / shortest:.3f}x the shortest, clearance '
                       f'{clearance / radius:.2f}x the radius')


def sight(run, grid, robot):
    """Return what the robot's laser could have seen along the run, at the laser's rate."""
    return seen_along_run(grid, run.poses, run.times[1] - run.times[0], robot.lasers[0])


def exploration_figures(course, run, grid, robot):
    """Return the exploration judge's verdict and figures: the coverage at each quarter too."""
    thresholds = task_thresholds(course.task, course.thresholds)
    reachable = reachable_free(grid, course.start[:2])
    judgement = judge_exploration(reachable, sight(run, grid, robot),
                                  thresholds.reference_coverage, thresholds)
    quarters = []
    for quarter in (1, 2, 3):
        part = ReferenceRun(run.times[:len(run.times) * quarter // 4],
                            run.poses[:len(run.times) * quarter // 4], [], None, '', None, 0.0)
        quarters.append(judge_exploration(reachable, sight(part, grid, robot), 1.0).coverage)
    over_time = ', '.join(f'{value:.2f}' for value in (*quarters, judgement.coverage))
    return judgement, (f'coverage {judgement.coverage:.3f}, '
                       f'{judgement.coverage / judgement.reference:.3f}x the reference; at each '
                       f'quarter of the sim time {over_time}')


def mapping_figures(course, run, grid, robot):
    """Return the mapping judge's verdict and figures of a reference run's map."""
    judgement = judge_map(sight(run, grid, robot), run.cells,
                          task_thresholds(course.task, course.thresholds))
    return judgement, (f'agreement {judgement.agreement:.3f}, coverage {judgement.coverage:.3f}'
                       f', false walls {judgement.false_walls:.3f}, missed walls '
                       f'{judgement.missed_walls:.3f}, beyond sight {judgement.unseen:.3f}')


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--smoke', action='store_true', help='the plus room only, in seconds')
    options = parser.parse_args(argv)
    courses = find_courses([shared_file('scenarios')])
    if options.smoke:
        courses = [course for course in courses if course.name in SMOKE]
    failed = 0
    for course in courses:
        run = run_reference(course)
        grid = Grid.from_map(load_map(course.map_file))
        robot = load_robot(course.robot_file)
        if course.task == MAPPING:
            judgement, figures = mapping_figures(course, run, grid, robot)
        elif course.task == EXPLORATION:
            judgement, figures = exploration_figures(course, run, grid, robot)
        else:
            judgement, figures = planning_figures(course, run, grid, robot.radius)
        passed = judgement.passed and run.exit_code == 0
        failed += not passed
        print(f'{course.name:22s} {"PASS" if passed else "FAIL"}  {figures}; '
              f'{run.sim_seconds:.1f} s sim, {run.sim_seconds / run.cpu_seconds:.0f}x real time '
              f'in CPU time{"" if passed else "; " + "; ".join(judgement.failures)}')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
