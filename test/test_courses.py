"""Every bundled course can be driven to the end in the bundled world, walls included."""

from pathlib import Path

import pytest

from stdr_lite.occupancy_map import load_map
from stdr_lite.share import shared_file
from stdr_lite.world import World
from waypoint_controller.control_law import ControllerConfig, CourseFollower
from waypoint_controller.waypoints import load_waypoints

COURSES = sorted((Path(__file__).resolve().parent.parent / 'waypoints').glob('*.txt'))
SIMULATION_DT = 0.02
STEPS_PER_CONTROL = 2


@pytest.mark.parametrize('course', COURSES, ids=[path.stem for path in COURSES])
def test_course_finishes_in_lab_room(course):
    world = World(load_map(shared_file('maps', 'lab_room.yaml')), max_radius=0.2)
    world.add_robot((1.0, 2.0, 0.0), 0.2)
    follower = CourseFollower(load_waypoints(course), ControllerConfig())
    command = (0.0, 0.0)
    for step in range(50 * 300):
        if step % STEPS_PER_CONTROL == 0:
            result = follower.update(tuple(world.poses[0]), SIMULATION_DT * STEPS_PER_CONTROL)
            command = (result.linear, result.angular)
            if result.finished:
                return
        world.step([command[0]], [command[1]], SIMULATION_DT)
    pytest.fail(f'{course.name}: stopped at waypoint {follower.next_index + 1} of '
                f'{len(follower.waypoints)}')
