"""Footprint checks against brute force, and the world's rules for blocked steps."""

import math

from map_fixtures import walled_room, write_map
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map, OccupancyMap
from stdr_lite.core.bodies import Bodies, PlacementError
from stdr_lite.core.collision import FootprintChecker

RESOLUTION = 0.05


def grid_map(occupied, origin=(0.0, 0.0, 0.0)):
    return OccupancyMap(cells=np.where(occupied, 100, 0).astype(np.int8),
                        resolution=RESOLUTION, origin=origin)


def brute_force_touches(occupied, origin, x, y, radius):
    """Distance from the centre to every occupied square and to the outside of the map."""
    origin_x, origin_y, yaw = origin
    dx, dy = x - origin_x, y - origin_y
    map_x = math.cos(yaw) * dx + math.sin(yaw) * dy
    map_y = -math.sin(yaw) * dx + math.cos(yaw) * dy
    height, width = occupied.shape
    width_m, height_m = width * RESOLUTION, height * RESOLUTION
    if not (0 <= map_x < width_m and 0 <= map_y < height_m):
        return True
    if min(map_x, map_y, width_m - map_x, height_m - map_y) < radius:
        return True
    for row, col in zip(*np.nonzero(occupied)):
        gap_x = max(abs(map_x - (col + 0.5) * RESOLUTION) - RESOLUTION / 2, 0.0)
        gap_y = max(abs(map_y - (row + 0.5) * RESOLUTION) - RESOLUTION / 2, 0.0)
        if math.hypot(gap_x, gap_y) < radius:
            return True
    return False


@pytest.mark.parametrize('origin', [(0.0, 0.0, 0.0), (-1.0, 0.5, 0.7)])
def test_checker_agrees_with_brute_force(origin):
    rng = np.random.default_rng(11)
    occupied = rng.random((40, 50)) < 0.02
    checker = FootprintChecker(grid_map(occupied, origin), max_radius=0.2)
    cos_yaw, sin_yaw = math.cos(origin[2]), math.sin(origin[2])
    local = rng.uniform([-0.3, -0.3], [2.8, 2.3], size=(400, 2))
    x = origin[0] + cos_yaw * local[:, 0] - sin_yaw * local[:, 1]
    y = origin[1] + sin_yaw * local[:, 0] + cos_yaw * local[:, 1]
    radius = rng.uniform(0.05, 0.2, size=400)
    expected = [brute_force_touches(occupied, origin, *args) for args in zip(x, y, radius)]
    assert checker.touches(x, y, radius).tolist() == expected
    assert 50 < sum(expected) < 350


def test_clear_for_motion_holds_everywhere_a_short_step_can_reach():
    rng = np.random.default_rng(3)
    occupied = rng.random((30, 40)) < 0.02
    checker = FootprintChecker(grid_map(occupied), max_radius=0.2)
    x, y = rng.uniform(-0.2, 2.2, 3000), rng.uniform(-0.2, 1.7, 3000)
    step, radius = 0.1, 0.15
    clear = checker.clear_for_motion(x, y, step, radius)
    assert 0 < clear.sum() < clear.size
    angles = np.linspace(0.0, 2.0 * math.pi, 24, endpoint=False)
    for start_x, start_y in zip(x[clear], y[clear]):
        for distance in (0.0, 0.5 * step, step):
            ends = zip(start_x + distance * np.cos(angles), start_y + distance * np.sin(angles))
            assert not any(brute_force_touches(occupied, (0.0, 0.0, 0.0), end_x, end_y, radius)
                           for end_x, end_y in ends)
    assert clear.sum() > checker.clear_for_motion(x, y, 2.0 * step, radius).sum()


def test_circle_exactly_clear_of_a_wall_does_not_touch_it():
    occupied = np.zeros((20, 20), dtype=bool)
    occupied[:, 10] = True
    checker = FootprintChecker(grid_map(occupied), max_radius=0.2)
    wall_face = 10 * RESOLUTION
    assert not checker.touches(wall_face - 0.2, 0.5, 0.2)
    assert checker.touches(wall_face - 0.2 + 1e-9, 0.5, 0.2)


def one_cell_wall_world(integrator, wall_col=100):
    occupied = np.zeros((60, 200), dtype=bool)
    occupied[:, wall_col] = True
    return Bodies(grid_map(occupied), max_radius=0.2, integrator=integrator)


@pytest.mark.parametrize('integrator', ['euler', 'arc'])
@pytest.mark.parametrize('start_x', [3.0, 3.13, 3.37, 3.49])
def test_no_tunnelling_through_a_one_cell_wall_at_5_mps_and_10_hz(integrator, start_x):
    world = one_cell_wall_world(integrator)
    world.add_body((start_x, 1.5, 0.0), 0.2)
    for _ in range(40):
        world.step([5.0], [0.0], 0.1)
    wall_face = 100 * RESOLUTION
    assert world.poses[0, 0] + 0.2 <= wall_face
    assert world.poses[0, 0] > wall_face - 0.2 - 0.5


def test_blocked_step_is_rejected_whole():
    world = one_cell_wall_world('euler')
    world.add_body((4.79, 1.5, 0.0), 0.2)
    before = world.poses.copy()
    moved = world.step([1.0], [0.5], 0.02)
    assert np.array_equal(world.poses, before)
    assert moved.tolist() == [False]


def test_robot_against_a_wall_may_rotate_and_drive_away():
    world = one_cell_wall_world('euler')
    world.add_body((4.79, 1.5, 0.0), 0.2)
    world.step([1.0], [0.0], 0.02)
    assert world.poses[0, 0] == 4.79
    assert world.step([0.0], [1.0], 0.1).tolist() == [True]
    assert world.poses[0, 2] == pytest.approx(0.1)
    world.step([-0.5], [0.0], 0.1)
    assert world.poses[0, 0] < 4.79 - 0.04


def test_each_robot_is_judged_on_its_own_step():
    world = one_cell_wall_world('arc')
    world.add_body((4.79, 1.5, 0.0), 0.2)
    world.add_body((2.0, 1.5, 0.0), 0.2)
    assert world.step([1.0, 1.0], [0.0, 0.0], 0.1).tolist() == [False, True]
    assert world.poses[:, 0] == pytest.approx([4.79, 2.1])


def test_the_map_edge_is_a_wall(tmp_path):
    open_field = np.full((40, 40), 255)
    world = Bodies(load_map(write_map(tmp_path, open_field)), max_radius=0.2)
    world.add_body((1.0, 1.0, math.pi), 0.2)
    for _ in range(100):
        world.step([1.0], [0.0], 0.05)
    assert world.poses[0, 0] == pytest.approx(0.2, abs=0.05 + 1e-9)
    assert world.poses[0, 0] >= 0.2


@pytest.mark.parametrize('pose, problem', [((0.1, 1.0, 0.0), 'touches a wall'),
                                           ((5.0, 1.0, 0.0), 'off the map'),
                                           ((1.0, math.nan, 0.0), 'not finite')])
def test_impossible_placements_are_refused(pose, problem):
    world = Bodies(grid_map(walled_room(40, 40) == 0), max_radius=0.2)
    with pytest.raises(PlacementError, match=problem):
        world.add_body(pose, 0.2)
    assert world.body_count == 0


@pytest.mark.parametrize('integrator', ['euler', 'arc'])
def test_no_step_ends_in_a_wall_or_another_body(integrator):
    """
    Stepped at random into walls and each other, no body ever ends where it cannot stand.

    Among the bodies are a square, a sliding obstacle and an omni robot moving sideways; the
    steps walls refuse and the steps other bodies refuse are both met many times.
    """
    rng = np.random.default_rng(5)
    occupied = walled_room(60, 50) == 0
    occupied[20:30, 25:28] = True
    world = Bodies(grid_map(occupied), max_radius=0.3, integrator=integrator)
    for pose in [(0.5, 0.5, 0.0), (0.9, 0.5, 3.0), (2.4, 1.2, 1.0), (1.0, 2.0, -1.0)]:
        world.add_body(pose, 0.2)
    square = ((-0.15, -0.15), (0.15, -0.15), (0.15, 0.15), (-0.15, 0.15))
    world.add_body((2.2, 0.5, 0.3), math.hypot(0.15, 0.15), square)
    headings = [np.nan, np.nan, 0.7, np.nan, np.nan]
    refused = 0
    for _ in range(300):
        linear, angular = rng.uniform(-1.5, 1.5, 5), rng.uniform(-2.0, 2.0, 5)
        lateral = np.where(np.arange(5) == 3, rng.uniform(-1.0, 1.0, 5), 0.0)
        linear[rng.random(5) < 0.1] = 0.0
        before = world.poses.copy()
        moved = world.step(linear, angular, 0.05, headings, lateral)
        assert np.array_equal(world.poses[~moved], before[~moved])
        for body in range(world.body_count):
            world.check_placement(world.poses[body], world.radii[body], ignore=body,
                                  shape=world.shapes[body])
        refused += int(np.sum(~moved & (linear != 0.0)))
    assert refused > 10
    assert not np.array_equal(world.poses[:, :2], [[0.5, 0.5], [0.9, 0.5], [2.4, 1.2],
                                                   [1.0, 2.0], [2.2, 0.5]])


def test_a_step_of_no_finite_length_is_refused_at_once():
    world = Bodies(grid_map(walled_room(40, 40) == 0), max_radius=0.3)
    world.add_body((0.5, 0.5, 0.0), 0.2)
    world.add_body((1.5, 1.5, 0.0), 0.2, ((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)))
    moved = world.step([math.inf, 0.0], [0.0, math.nan], 0.05)
    assert not moved.any()
    assert world.poses.tolist() == [[0.5, 0.5, 0.0], [1.5, 1.5, 0.0]]
