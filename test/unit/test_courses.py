"""Every bundled course is driven to FINISHED in the bundled world, walls included."""

from pathlib import Path

import pytest
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import BUNDLED_MAP, shared_file
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.simulation import Simulation, SimulationSettings
from waypoint_controller.config import ControllerConfig
from waypoint_controller.control_law import PlannedLaw
from waypoint_lab.lifecycle import RunLifecycle, RunRules
from waypoint_lab.waypoints import load_waypoints

COURSES = sorted((Path(__file__).resolve().parents[2] / 'waypoints').glob('*.txt'))
STEPS_PER_CONTROL = 2


@pytest.mark.parametrize('course', COURSES, ids=[path.stem for path in COURSES])
def test_course_finishes_in_lab_room(course):
    robot = RobotEntry('robot0', RobotDescription(0.2, (1.0, 2.0, 0.0)), (1.0, 2.0, 0.0))
    simulation = Simulation(load_map(shared_file(*BUNDLED_MAP)), SimulationSettings(50.0),
                            [robot])
    waypoints = load_waypoints(course)
    run = RunLifecycle(waypoints, PlannedLaw(waypoints, ControllerConfig()),
                       RunRules(control_period_ns=STEPS_PER_CONTROL * simulation.dt_ns))
    for _ in range(50 * 300):
        outcome = run.observe(simulation.time_ns, simulation.pose('robot0'))
        assert outcome.exit_code != 1, outcome.problem
        if outcome.exit_code == 0:
            return
        if outcome.command is not None:
            simulation.command('robot0', *outcome.command)
        simulation.step()
    pytest.fail(f'{course.name}: stopped at waypoint {run.next_index + 1} of '
                f'{len(waypoints)}')
