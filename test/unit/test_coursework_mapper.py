"""The reference mapper, fed the simulator's own laser along a drive, passes the mapping judge."""

import math

from coursework_answers.mapper import LogOddsMapper
from courseworks.grids import Grid
from courseworks.mapping import judge_map, Laser, seen_along
import pytest
from stdr_lite.core.loading import load_world, robot_file
from stdr_lite.core.robot_description import load_robot

STEPS_PER_SCAN = 5


@pytest.fixture(scope='module')
def drive():
    """Drive the small robot down the factory's corridor and into a room, scanning at 10 Hz."""
    world = load_world('factory', robots=[('robot0', (1.5, 8.0, 0.0), 'small_laser_robot')])
    spec = load_robot(robot_file('small_laser_robot')).lasers[0]
    grid = Grid.from_map(world.occupancy_map)
    mapper = LogOddsMapper(grid.shape, grid.resolution, grid.origin)
    increment = (spec.max_angle - spec.min_angle) / (spec.num_rays - 1)
    poses = []
    for step in range(1500):
        turning = 600 <= step < 700
        world.command('robot0', 0.0 if turning else 0.5, -math.pi / 4 if turning else 0.0)
        world.step()
        if step % STEPS_PER_SCAN == 0:
            pose = world.pose('robot0')
            poses.append(pose)
            mapper.add_scan(pose, spec.min_angle, increment,
                            world.sensor_readings('robot0')['laser_0'], spec.max_range)
    laser = Laser(spec.min_angle, spec.max_angle, spec.num_rays, spec.max_range)
    return grid, mapper, seen_along(grid, poses, laser)


def test_the_reference_map_passes_the_judge(drive):
    grid, mapper, sight = drive
    judgement = judge_map(sight, mapper.cells())
    assert judgement.passed, judgement
    assert judgement.agreement > 0.95 and judgement.coverage > 0.9


def test_cells_no_ray_crossed_stay_unknown_and_the_rest_are_probabilities(drive):
    grid, mapper, sight = drive
    cells = mapper.cells()
    assert (cells[~mapper.observed] == -1).all()
    assert cells[mapper.observed].min() >= 0 and cells[mapper.observed].max() <= 100
    store_room = grid.cell_of(21.0, 12.5)
    assert cells[store_room] == -1
