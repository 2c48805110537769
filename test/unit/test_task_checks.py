"""A coursework's line on grade_lab's sheet, from crafted runs and maps: its judge, one line."""

from courseworks.grids import Grid
from courseworks.mapping import seen_along
from lab_grader.courses import read_course
from lab_grader.task_checks import task_checks
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map, OccupancyMap
from simple_robot_control.share import shared_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.run import Run


@pytest.fixture(scope='module')
def mapping():
    """Give the plus room's mapping course, a run standing at its start, and what it saw."""
    course = read_course(shared_file('scenarios', 'plus_room_mapping.txt'))
    world = load_map(course.map_file)
    times = np.arange(0.0, 2.0, 0.02)
    run = Run(course, times, np.tile(course.start, (len(times), 1)))
    laser = load_robot(course.robot_file).lasers[0]
    sight = seen_along(Grid.from_map(world), [course.start], laser)
    return course, world, run, sight


def mapping_line(course, run, submitted):
    (check,) = task_checks(course, run, submitted)
    assert check.name == 'mapping' and '\n' not in check.evidence
    return check


def map_of(world, cells):
    return OccupancyMap(cells.astype(np.int8), world.resolution, world.origin)


def test_the_world_as_the_laser_saw_it_passes(mapping):
    course, world, run, sight = mapping
    cells = np.where(sight.seen, world.cells, -1)
    check = mapping_line(course, run, map_of(world, cells))
    assert check.passed and check.evidence.startswith('agreement 100.0%')


def test_the_whole_map_copied_fails_as_not_built_from_the_laser(mapping):
    course, world, run, _ = mapping
    check = mapping_line(course, run, map_of(world, world.cells))
    assert not check.passed and 'not built from the laser alone' in check.evidence


def test_invented_walls_fail_as_false_walls(mapping):
    course, world, run, sight = mapping
    cells = np.where(sight.seen, world.cells, -1)
    cells[sight.seen_free] = 100
    check = mapping_line(course, run, map_of(world, cells))
    assert not check.passed and 'false walls' in check.evidence.split('(')[0]


@pytest.mark.parametrize('submitted, line', [
    (None, 'no map on /coursework_map during the run'),
    ('/coursework_map: a grid of 0x0 cells', 'the last map was no map: /coursework_map: a grid'),
])
def test_no_map_fails_saying_why(mapping, submitted, line):
    course, _, run, _ = mapping
    check = mapping_line(course, run, submitted)
    assert not check.passed and check.evidence.startswith(line)


def test_a_map_of_another_geometry_fails_naming_both(mapping):
    course, world, run, _ = mapping
    small = OccupancyMap(np.full((10, 10), -1, dtype=np.int8), 0.1, (0.0, 0.0, 0.0))
    check = mapping_line(course, run, small)
    assert not check.passed and check.evidence.startswith(
        'the map is 10x10 cells of 0.1 m from (0, 0); the world is 300x300 of 0.05 m')
