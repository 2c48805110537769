"""A coursework's line on grade_lab's sheet, from crafted runs and maps: its judge, one line."""

from courseworks.courses import read_course
from courseworks.grids import Grid
from courseworks.mapping import AGREED, FALSE_WALL, seen_along
from lab_grader.task_checks import judge_task
from lab_grader.task_picture import render_task_picture
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
    (check,), _ = judge_task(course, run, submitted)
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


def coarse(world, cells, factor):
    """Return cells as a mapper of cells factor times coarser draws them: walls in a block win."""
    rows, columns = (size // factor for size in cells.shape)
    blocks = cells[:rows * factor, :columns * factor].reshape(rows, factor, columns, factor)
    drawn = np.where((blocks == 100).any(axis=(1, 3)), 100,
                     np.where((blocks == 0).any(axis=(1, 3)), 0, -1))
    return OccupancyMap(drawn.astype(np.int8), world.resolution * factor, world.origin)


def test_a_coarser_map_is_judged_on_the_worlds_cells_it_covers(mapping):
    """A student's 0.25 m grid of the plus room (0.05 m cells), drawn right: PASS."""
    course, world, run, sight = mapping
    check = mapping_line(course, run, coarse(world, np.where(sight.seen, world.cells, -1), 5))
    assert check.passed, check.evidence
    wrong = coarse(world, np.where(sight.seen, 100, -1), 5)
    assert 'false walls' in mapping_line(course, run, wrong).evidence


def test_a_map_elsewhere_or_turned_fails_saying_so(mapping):
    course, world, run, _ = mapping
    small = OccupancyMap(np.full((10, 10), 0, dtype=np.int8), 0.1, (-5.0, -5.0, 0.0))
    check = mapping_line(course, run, small)
    assert not check.passed and 'coverage 0.0%' in check.evidence
    turned = OccupancyMap(world.cells, world.resolution, (0.0, 0.0, 0.5))
    check = mapping_line(course, run, turned)
    assert not check.passed and check.evidence == (
        'the map is turned by 0.5 rad from (0, 0): a map along x is judged (origin yaw 0)')


def test_the_judges_reading_of_each_cell_is_drawn_for_the_report(mapping, tmp_path):
    """task.png: agreed where the map is right, false walls where it invents them."""
    course, world, run, sight = mapping
    right = np.where(sight.seen, world.cells, -1)
    _, picture = judge_task(course, run, map_of(world, right))
    assert picture.codes.shape == world.cells.shape
    assert np.count_nonzero(picture.codes == AGREED) == np.count_nonzero(sight.seen)
    invented = right.copy()
    invented[sight.seen_free] = 100
    _, wrong = judge_task(course, run, map_of(world, invented))
    assert np.count_nonzero(wrong.codes == FALSE_WALL) > 0
    assert np.array_equal(wrong.submitted.cells, invented)
    render_task_picture(wrong, run.poses[:, :2], tmp_path / 'task.png')
    png = (tmp_path / 'task.png').read_bytes()
    assert png[:8] == b'\x89PNG\r\n\x1a\n'
    # The map as published is drawn beside the reading: a picture wider than one panel.
    assert int.from_bytes(png[16:20], 'big') > int.from_bytes(png[20:24], 'big') * 1.8
    exploration = read_course(shared_file('scenarios', 'plus_room_exploration.txt'))
    _, seen = judge_task(exploration, Run(exploration, run.times, np.tile(
        exploration.start, (len(run.times), 1))))
    assert {int(code) for code in np.unique(seen.codes)} == {0, 1, 2}
