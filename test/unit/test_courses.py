"""Every bundled course can be driven to the end in the bundled world, walls included."""

from pathlib import Path

import pytest
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import BUNDLED_MAP, shared_file
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.simulation import Simulation, SimulationSettings
from waypoint_controller.config import ControllerConfig
from waypoint_controller.control_law import CourseFollower
from waypoint_lab.waypoints import load_waypoints

COURSES = sorted((Path(__file__).resolve().parents[2] / 'waypoints').glob('*.txt'))
STEPS_PER_CONTROL = 2


@pytest.mark.parametrize('course', COURSES, ids=[path.stem for path in COURSES])
def test_course_finishes_in_lab_room(course):
    robot = RobotEntry('robot0', RobotDescription(0.2, (1.0, 2.0, 0.0)), (1.0, 2.0, 0.0))
    simulation = Simulation(load_map(shared_file(*BUNDLED_MAP)), SimulationSettings(50.0),
                            [robot])
    follower = CourseFollower(load_waypoints(course), ControllerConfig())
    for step in range(50 * 300):
        if step % STEPS_PER_CONTROL == 0:
            result = follower.update(simulation.pose('robot0'),
                                     simulation.dt * STEPS_PER_CONTROL)
            if result.finished:
                return
            simulation.command('robot0', result.linear, result.angular)
        simulation.step()
    pytest.fail(f'{course.name}: stopped at waypoint {follower.next_index + 1} of '
                f'{len(follower.waypoints)}')
