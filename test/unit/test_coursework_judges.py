"""The courseworks' grid, rays and judges, on crafted worlds and crafted submissions."""

import math

from courseworks.exploration import judge_exploration, reachable_free
from courseworks.grids import Grid, GridError, inflate, path_lengths, region_of
from courseworks.mapping import judge_map, Laser, MapThresholds, seen_along
from courseworks.planning import clearance_along, judge_planning, plan_legs
from courseworks.rays import integrate_ranges, trace
import numpy as np
import pytest
from simple_robot_control.occupancy_map import FREE, OccupancyMap, OCCUPIED

RESOLUTION = 0.1
LASER = Laser(-2.0944, 2.0944, 241, 4.0)


def room(rows=60, columns=80):
    """Return a walled room of 8 m x 6 m at 0.1 m, a wall with a door across its middle."""
    walls = np.zeros((rows, columns), dtype=bool)
    walls[0, :] = walls[-1, :] = walls[:, 0] = walls[:, -1] = True
    walls[:, 40] = True
    walls[25:35, 40] = False
    return Grid(walls, RESOLUTION, (0.0, 0.0))


def as_cells(walls):
    return np.where(walls, OCCUPIED, FREE).astype(np.int8)


def test_cells_and_metres_agree_and_off_the_map_is_none():
    grid = room()
    assert grid.cell_of(*grid.centre_of(12, 34)) == (12, 34)
    assert grid.cell_of(-0.01, 1.0) is None and grid.cell_of(1.0, 6.0) is None


def test_a_rotated_map_is_refused_in_one_line():
    cells = np.zeros((4, 4), dtype=np.int8)
    with pytest.raises(GridError, match=r'^rot.yaml: a rotated map \(origin yaw 0.5\)'):
        Grid.from_map(OccupancyMap(cells, 0.05, (0.0, 0.0, 0.5), 'rot.yaml'))


def test_inflation_grows_walls_by_the_radius():
    walls = np.zeros((11, 11), dtype=bool)
    walls[5, 5] = True
    grown = inflate(Grid(walls, RESOLUTION, (0.0, 0.0)), 0.2)
    assert grown[5, 3] and grown[5, 7] and grown[3, 5] and not grown[5, 2]
    assert grown[4, 4] and not grown[3, 3]


def test_shortest_paths_go_straight_diagonal_and_around_corners():
    free = np.ones((10, 10), dtype=bool)
    lengths = path_lengths(free, (0, 0), RESOLUTION)
    assert lengths[0, 9] == pytest.approx(0.9)
    assert lengths[9, 9] == pytest.approx(0.9 * math.sqrt(2))
    # Two walls touching at a corner: no diagonal squeezes between them.
    free[1, 0] = free[0, 1] = False
    assert math.isinf(path_lengths(free, (0, 0), RESOLUTION)[1, 1])
    assert np.isinf(path_lengths(free, (1, 0), RESOLUTION)).all()


def test_regions_join_only_through_free_cells():
    grid = room()
    left = region_of(~grid.walls, (10, 10))
    assert left[10, 70] and not left[0, 0]
    grid.walls[25:35, 40] = True
    assert not region_of(~grid.walls, (10, 10))[10, 70]


def test_a_ray_visits_each_cell_up_to_the_first_wall():
    walls = np.zeros((3, 10), dtype=bool)
    walls[1, 6] = True
    free, hit = np.zeros((3, 10), np.int32), np.zeros((3, 10), np.int32)
    travelled, row, column = trace(walls, 0.5, 1.5, 0.0, 100.0, free, hit)
    assert travelled == pytest.approx(5.5) and (row, column) == (1, 6)
    assert free[1].tolist() == [1, 1, 1, 1, 1, 1, 0, 0, 0, 0] and hit[1, 6] == 1
    free[:] = 0
    assert trace(walls, 0.5, 1.5, 0.0, 2.0, free, hit)[0] == 2.0
    assert free[1].tolist()[:4] == [1, 1, 1, 0]


def test_a_measured_range_is_free_space_then_a_wall_and_no_return_is_free_only():
    free, walls = np.zeros((3, 10), np.int32), np.zeros((3, 10), np.int32)
    no_walls = np.zeros((3, 10), dtype=bool)
    integrate_ranges(0.5, 1.5, 0.0, 0.0, 0.0, np.array([3.0]), 5.0, free, walls, no_walls)
    assert free[1].tolist() == [1, 1, 1, 0, 0, 0, 0, 0, 0, 0] and walls[1, 3] == 1
    integrate_ranges(0.5, 1.5, 0.0, 0.0, 0.0, np.array([np.inf, np.nan, -1.0]), 5.0, free,
                     walls, no_walls)
    assert walls.sum() == 1 and free[1, 5] == 1 and free[1, 6] == 0


@pytest.fixture(scope='module')
def judged_room():
    """Return the room, and what a laser saw driving along the left half's middle."""
    grid = room()
    path = [(x, 3.0, 0.0) for x in np.arange(0.5, 3.5, 0.25)]
    return grid, seen_along(grid, path, LASER)


def test_the_laser_sees_the_left_room_and_through_the_door_but_not_behind_walls(judged_room):
    grid, sight = judged_room
    assert sight.seen_free[30, 20] and sight.seen_free[30, 40]
    assert sight.seen_wall[10, 40] and sight.seen_free[30, 45]
    assert not sight.seen_free[5, 70] and not sight.seen.any(axis=0)[79]


def test_a_true_map_passes_and_a_cell_off_still_passes(judged_room):
    grid, sight = judged_room
    truth = as_cells(grid.walls)
    truth[~sight.seen] = -1
    judgement = judge_map(sight, truth)
    assert judgement.passed, judgement.failures
    assert (judgement.agreement, judgement.false_walls, judgement.missed_walls,
            judgement.coverage) == (1.0, 0.0, 0.0, 1.0)
    assert judge_map(sight, np.roll(truth, 1, axis=1)).passed


def test_invented_walls_fail_as_false_walls(judged_room):
    grid, sight = judged_room
    invented = as_cells(grid.walls)
    invented[~sight.seen] = -1
    invented[10:50, 10:30] = OCCUPIED
    judgement = judge_map(sight, invented)
    assert not judgement.passed
    assert any(failure.startswith('false walls') for failure in judgement.failures)


def test_an_empty_map_fails_on_coverage(judged_room):
    _, sight = judged_room
    judgement = judge_map(sight, np.full(sight.seen.shape, -1, dtype=np.int8))
    assert judgement.coverage == 0.0 and judgement.failures[-1].startswith('coverage 0.0%')


def test_a_map_copied_from_the_world_fails_as_not_built_from_the_laser(judged_room):
    grid, sight = judged_room
    judgement = judge_map(sight, as_cells(grid.walls))
    assert judgement.agreement == 1.0
    assert judgement.failures == (
        f"the map knows {judgement.unseen:.1%} of its cells where no ray from the robot's "
        'path reached: not built from the laser alone',)
    assert judge_map(sight, as_cells(grid.walls), MapThresholds(max_unseen=1.0)).passed


def test_a_map_of_another_size_is_refused(judged_room):
    _, sight = judged_room
    with pytest.raises(ValueError, match='a map of 10x10 cells, the world has 80x60'):
        judge_map(sight, np.zeros((10, 10), dtype=np.int8))


def test_an_explorer_that_stands_still_sees_too_little(judged_room):
    grid, driven = judged_room
    reachable = reachable_free(grid, (0.5, 3.0))
    assert reachable[30, 70] and not reachable[0, 0]
    still = seen_along(grid, [(0.5, 3.0, math.pi)], LASER)
    reference = judge_exploration(reachable, driven, 0.0).coverage
    assert judge_exploration(reachable, driven, reference).passed
    judgement = judge_exploration(reachable, still, reference)
    assert judgement.coverage < 0.25 and judgement.failures[0].startswith(
        f'saw {judgement.coverage:.1%} of the reachable free space, needs ')
    assert not reachable_free(grid, (-1.0, 3.0)).any()


def test_legs_know_unreachable_goals_and_each_optimum():
    grid = room()
    grid.walls[40:59, 60] = True
    grid.walls[40, 60:79] = True
    legs = plan_legs(grid, 0.15, (1.0, 3.0, 0.0), [(3.0, 3.0, 0), (7.0, 5.0, 0), (6.0, 1.0, 0)])
    assert [leg.reachable for leg in legs] == [True, False, True]
    assert legs[0].optimum == pytest.approx(2.0)
    # Through the door: never shorter than the straight line from the first goal.
    assert legs[2].optimum >= math.hypot(3.0, 2.0)


def test_planning_fails_a_long_way_round_an_unreported_or_false_unreachable_and_a_touch():
    grid = room()
    legs = plan_legs(grid, 0.15, (1.0, 3.0, 0.0), [(3.0, 3.0, 0), (2.0, 9.0, 0)])
    straight = [(x, 3.0) for x in np.linspace(1.0, 3.0, 21)]
    clearance = clearance_along(grid, straight)[0]
    judgement = judge_planning(legs, straight, {1: 20}, {2}, 0.15, clearance)
    assert judgement.passed, judgement.failures
    assert judgement.legs[0].ratio == pytest.approx(1.0)
    detour = [(1.0, 3.0), (1.0, 5.0), (3.0, 5.0), (3.0, 3.0)]
    failures = judge_planning(legs, detour, {1: 3}, set(), 0.15, clearance).failures
    assert failures[0].startswith('goal 1: drove 6.00 m, 3.00x the shortest 2.00 m')
    assert failures[1] == 'goal 2 is unreachable and was not reported so'
    failures = judge_planning(legs, straight, {}, {1, 2}, 0.15, clearance).failures
    assert failures[:2] == ('goal 1 was reported unreachable; the judge reaches it by 2.00 m',
                            'goal 1 was not reached')
    scrape = [(1.0, 3.0), (1.0, 0.12)]
    least, where = clearance_along(grid, scrape)
    assert least < 0.15 and where == (1.0, 0.12)
    assert judge_planning(legs, straight, {1: 20}, {2}, 0.15, least).failures[-1].startswith(
        'touched a wall: the centre came within')
