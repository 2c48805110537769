"""
A course run by the reference answers in the simulation core, no ROS: for tests and benches.

The planner-controller's law (route_law.py) drives the course's goals through the lab's run
lifecycle, exploring first where the course explores (explorer_law.py); where the course maps
or explores, the log-odds mapper (mapper.py) builds the map from the
robot's laser at the laser's rate and the law plans on it, a new map every MAP_EVERY scans, as
the nodes do (occupancy_mapper and planner_controller with map_topic); elsewhere the law plans
on the world's map. What the nodes add is ROS; the decisions are these.
"""

from dataclasses import dataclass
import time

from coursework_answers.explorer_law import ExplorerLaw
from coursework_answers.mapper import LogOddsMapper
from coursework_answers.route_law import RouteLaw
from courseworks.grids import Grid
from courseworks.mapping import scan_every
from courseworks.names import EXPLORATION, HIDES_MAP
import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.loading import load_world, robot_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.course import Course
from waypoint_lab.lifecycle import RunLifecycle
from waypoint_lab.status import parse_status, Status

# The margin planner_controller keeps by default, and how often occupancy_mapper publishes.
MARGIN = 0.15
MAP_EVERY = 10


@dataclass
class ReferenceRun:
    """What a run left: the true path (a pose per step), the statuses, the map, the costs."""

    times: np.ndarray
    poses: np.ndarray
    statuses: list[tuple[int, Status]]
    exit_code: int | None
    problem: str
    cells: np.ndarray | None
    cpu_seconds: float

    @property
    def sim_seconds(self) -> float:
        return float(self.times[-1]) if len(self.times) else 0.0


def run_reference(course: Course) -> ReferenceRun:
    """Run course (its world, robot, start, goals, time limit) with the reference answers."""
    started = time.process_time()
    world = load_world(course.map_file, robots=[('robot0', course.start, course.robot_file)])
    truth = Grid.from_map(world.occupancy_map)
    robot = load_robot(robot_file(course.robot_file))
    law = (ExplorerLaw(course.waypoints, robot.radius, MARGIN, explore_for=course.time_limit)
           if course.task == EXPLORATION else RouteLaw(course.waypoints, robot.radius, MARGIN))
    mapper = laser = None
    if course.task in HIDES_MAP:
        laser = robot.lasers[0]
        mapper = LogOddsMapper(truth.shape, truth.resolution, truth.origin)
        every = scan_every(laser, world.dt)
        increment = (laser.max_angle - laser.min_angle) / max(laser.num_rays - 1, 1)
    else:
        law.use_map(world.occupancy_map)
    run = RunLifecycle(course.waypoints, law)
    command, statuses, poses, scans = (0.0, 0.0), [], [], 0
    outcome = None
    for step in range(round(course.time_limit / world.dt) + 1):
        pose = world.pose('robot0')
        poses.append(pose)
        if mapper is not None and step % every == 0:
            mapper.add_scan(pose, laser.min_angle, increment,
                            world.sensor_readings('robot0')[laser.frame_id], laser.max_range)
            scans += 1
            if scans % MAP_EVERY == 1:
                law.use_map(OccupancyMap(mapper.cells(), truth.resolution,
                                         (*truth.origin, 0.0)))
        outcome = run.observe(step * round(world.dt * 1e9), pose)
        statuses += [(step, parse_status(text)) for text in outcome.statuses]
        command = outcome.command or command
        if outcome.exit_code is not None:
            break
        world.command('robot0', *command)
        world.step()
    return ReferenceRun(np.arange(len(poses)) * world.dt, np.asarray(poses), statuses,
                        outcome.exit_code, outcome.problem,
                        None if mapper is None else mapper.cells(),
                        time.process_time() - started)
