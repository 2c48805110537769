"""Polygon footprints: walls, other bodies and sensors see the polygon, not a circle."""

import math

import numpy as np
import pytest
import shapely
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.bodies import Bodies, PlacementError
from stdr_lite.core.collision import FootprintChecker
from stdr_lite.core.footprints import placed
from stdr_lite.core.robot_description import LaserSpec, Noise
from stdr_lite.core.sensors import RangeFinder, read_sensors

RESOLUTION = 0.05
SQUARE = ((-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2))
CIRCUMRADIUS = math.hypot(0.2, 0.2)
# A wall across a 6 m x 3 m room at x = 3 m, with a gap 0.45 m wide (9 cells) centred on
# y = 1.525 m.
GAP_ROWS = (26, 35)
GAP = (GAP_ROWS[1] - GAP_ROWS[0]) * RESOLUTION
GAP_MIDDLE = 0.5 * sum(GAP_ROWS) * RESOLUTION


def grid_map(occupied):
    return OccupancyMap(cells=np.where(occupied, 100, 0).astype(np.int8),
                        resolution=RESOLUTION, origin=(0.0, 0.0, 0.0))


def room_with_a_gap():
    occupied = np.zeros((60, 120), dtype=bool)
    occupied[[0, -1], :] = occupied[:, [0, -1]] = True
    occupied[:, 60] = True
    occupied[GAP_ROWS[0]:GAP_ROWS[1], 60] = False
    return grid_map(occupied)


def drive_through(radius, shape, heading):
    """Drive a body from x 2 m towards +x for 3 s at 1 m/s; return where it ends."""
    world = Bodies(room_with_a_gap(), max_radius=0.3)
    world.add_body((2.0, GAP_MIDDLE, heading), radius, shape)
    for _ in range(60):
        world.step([1.0], [0.0], 0.05, travel_headings=[0.0])
    return world.poses[0]


def test_a_square_passes_a_gap_its_circumscribed_disc_cannot():
    assert GAP == pytest.approx(0.45)
    assert drive_through(CIRCUMRADIUS, SQUARE, 0.0)[0] > 4.0
    assert drive_through(CIRCUMRADIUS, None, 0.0)[0] < 3.0


def test_a_square_turned_across_a_gap_narrower_than_it_stops_where_its_inner_disc_passes():
    assert 2 * CIRCUMRADIUS > GAP > 2 * 0.2
    assert drive_through(CIRCUMRADIUS, SQUARE, math.pi / 4)[0] < 3.0
    assert drive_through(0.2, None, 0.0)[0] > 4.0


def test_a_square_against_a_wall_cannot_turn_into_it_but_a_disc_can():
    occupied = np.zeros((60, 120), dtype=bool)
    occupied[:, 60] = True
    world = Bodies(grid_map(occupied), max_radius=0.3)
    world.add_body((2.75, 1.5, 0.0), CIRCUMRADIUS, SQUARE)
    world.add_body((2.75, 0.5, 0.0), 0.2)
    moved = world.step([0.0, 0.0], [1.0, 1.0], 0.5)
    assert moved.tolist() == [False, True]
    assert world.poses[0].tolist() == [2.75, 1.5, 0.0]
    assert world.step([-0.5, 0.0], [0.0, 0.0], 0.1).tolist() == [True, True]
    assert world.step([0.0, 0.0], [1.0, 1.0], 0.5).tolist() == [True, True]


@pytest.mark.parametrize('integrator', ['euler', 'arc'])
@pytest.mark.parametrize('heading', [0.0, 0.3, math.pi / 4])
def test_no_polygon_tunnels_through_a_one_cell_wall(integrator, heading):
    occupied = np.zeros((60, 200), dtype=bool)
    occupied[:, 100] = True
    world = Bodies(grid_map(occupied), max_radius=0.3, integrator=integrator)
    world.add_body((3.0, 1.5, heading), CIRCUMRADIUS, SQUARE)
    for _ in range(40):
        world.step([5.0], [0.0], 0.1, travel_headings=[0.0])
        corners = placed(SQUARE, world.poses[0])
        assert corners[:, 0].max() <= 100 * RESOLUTION


def test_the_polygon_check_agrees_with_shapely_on_random_poses():
    rng = np.random.default_rng(3)
    occupied = rng.random((40, 40)) < 0.04
    checker = FootprintChecker(grid_map(occupied), 0.3)
    cells = shapely.union_all([shapely.box(col * RESOLUTION, row * RESOLUTION,
                                           (col + 1) * RESOLUTION, (row + 1) * RESOLUTION)
                               for row, col in zip(*np.nonzero(occupied))])
    room = shapely.box(0.0, 0.0, 40 * RESOLUTION, 40 * RESOLUTION)
    triangle = ((0.25, 0.0), (-0.1, 0.15), (-0.1, -0.15))
    poses = np.column_stack([rng.uniform(0.0, 2.0, 400), rng.uniform(0.0, 2.0, 400),
                             rng.uniform(-math.pi, math.pi, 400)])
    touches = checker.polygon_touches(poses[:, 0], poses[:, 1], poses[:, 2], triangle)
    for pose, touching in zip(poses, touches):
        polygon = shapely.Polygon(placed(triangle, pose))
        overlap = shapely.intersection(polygon, cells).area + polygon.difference(room).area
        assert touching == (overlap > 1e-12), pose
    assert 50 < touches.sum() < 350


def test_bodies_never_overlap_a_polygon():
    occupied = np.zeros((80, 200), dtype=bool)
    occupied[[0, -1], :] = occupied[:, [0, -1]] = True
    world = Bodies(grid_map(occupied), max_radius=0.3)
    world.add_body((3.0, 2.0, 0.4), CIRCUMRADIUS, SQUARE)
    world.add_body((6.0, 2.0, math.pi), 0.2)
    world.add_body((4.5, 3.2, -math.pi / 2), CIRCUMRADIUS, SQUARE)
    for _ in range(200):
        world.step([0.5, 0.5, 0.3], [0.3, 0.0, -0.4], 0.05)
        first = shapely.Polygon(placed(SQUARE, world.poses[0]))
        disc = shapely.Point(world.poses[1, :2]).buffer(0.2, quad_segs=64)
        third = shapely.Polygon(placed(SQUARE, world.poses[2]))
        assert first.intersection(disc).area < 1e-9
        assert first.intersection(third).area < 1e-12
        assert third.intersection(disc).area < 1e-9
    assert world.poses[0, 0] > 3.5 and world.poses[1, 0] < 5.5


def test_a_polygon_cannot_be_placed_on_another_body():
    world = Bodies(grid_map(np.zeros((60, 120), dtype=bool)), max_radius=0.3)
    world.add_body((2.0, 1.5, 0.0), CIRCUMRADIUS, SQUARE)
    with pytest.raises(PlacementError, match='overlaps body 0'):
        world.add_body((2.35, 1.5, 0.0), 0.2)
    world.add_body((2.45, 1.5, 0.0), 0.2)
    with pytest.raises(PlacementError, match='a footprint of 4 corners at .* overlaps body 0'):
        world.add_body((2.0, 1.85, math.pi / 4), CIRCUMRADIUS, SQUARE)


def test_a_laser_sees_a_square_s_face_and_corner():
    finder = RangeFinder(grid_map(np.zeros((60, 120), dtype=bool)))
    laser = LaserSpec('laser_0', (0.0, 0.0, 0.0), 0.0, 0.0, 0.0, 2.5, 1, 10.0, Noise())
    poses = np.array([[1.0, 1.5, 0.0], [3.0, 1.5, 0.0], [3.0, 1.5, math.pi / 4]])
    radii = np.array([0.2, CIRCUMRADIUS, CIRCUMRADIUS])
    face, = read_sensors(finder, poses[:2], radii[:2], [None, SQUARE], [(0, laser)],
                         np.random.default_rng(0))
    assert face[0] == pytest.approx(2.0 - 0.2)
    corner, = read_sensors(finder, poses[[0, 2]], radii[[0, 2]], [None, SQUARE], [(0, laser)],
                           np.random.default_rng(0))
    assert corner[0] == pytest.approx(2.0 - CIRCUMRADIUS)
    own, = read_sensors(finder, poses[1:2], radii[1:2], [SQUARE], [(0, laser)],
                        np.random.default_rng(0))
    assert own[0] == np.inf
