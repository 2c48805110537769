"""Lasers and sonars against walls and robots, with and without the described noise."""

import math

from map_fixtures import walled_room, write_map
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.robot_description import LaserSpec, Noise, SonarSpec
from stdr_lite.core.sensors import RangeFinder, read_sensors

RESOLUTION = 0.05
# walled_room(200, 80) has one-cell walls: the free inside spans these bounds.
INSIDE = (0.05, 9.95, 0.05, 3.95)


def laser(noise=Noise(), rays=667, max_range=4.09, min_range=0.06):
    """Describe the lab's laser; with one ray, a single beam straight ahead."""
    half_fan = 2.0944 if rays > 1 else 0.0
    return LaserSpec('laser_0', (0.0, 0.0, 0.0), -half_fan, half_fan, min_range, max_range,
                     rays, 10.0, noise)


def sonar(cone=0.87, noise=Noise()):
    return SonarSpec('sonar_0', (0.0, 0.0, 0.0), cone, 0.15, 3.0, 10.0, noise)


@pytest.fixture
def finder(tmp_path):
    return RangeFinder(load_map(write_map(tmp_path, walled_room(200, 80))))


def exact_distance_to_walls(x, y, angle):
    """Where a ray from inside the room leaves the inside box."""
    low_x, high_x, low_y, high_y = INSIDE
    cos_a, sin_a = np.cos(angle), np.sin(angle)
    with np.errstate(divide='ignore'):
        along_x = np.where(cos_a > 0, (high_x - x) / cos_a, (low_x - x) / cos_a)
        along_y = np.where(sin_a > 0, (high_y - y) / sin_a, (low_y - y) / sin_a)
    return np.minimum(np.abs(along_x), np.abs(along_y))


def read(finder, poses, jobs, radii=None, seed=0):
    poses = np.asarray(poses, dtype=float)
    radii = np.full(len(poses), 0.2) if radii is None else np.asarray(radii)
    return read_sensors(finder, poses, radii, [None] * len(poses), jobs,
                        np.random.default_rng(seed))


def test_laser_reads_the_walls_within_one_cell(finder):
    pose = (2.0, 1.5, 0.3)
    ranges, = read(finder, [pose], [(0, laser())])
    angles = pose[2] + np.linspace(-2.0944, 2.0944, 667)
    exact = exact_distance_to_walls(pose[0], pose[1], angles)
    within = exact <= 4.09 - RESOLUTION
    assert within.sum() > 300
    assert np.all(np.abs(ranges[within] - exact[within]) <= RESOLUTION)
    assert np.all(np.isposinf(ranges[exact > 4.09 + RESOLUTION]))


def test_laser_facing_a_wall_at_a_known_distance(finder):
    ranges, = read(finder, [(7.45, 2.0, 0.0)], [(0, laser(rays=1, max_range=4.0))])
    assert ranges[0] == pytest.approx(2.5, abs=RESOLUTION)


def test_noise_has_the_described_mean_and_spread(finder):
    spec = laser(Noise(mean=0.05, std=0.02), rays=1, max_range=4.0)
    clean, = read(finder, [(7.45, 2.0, 0.0)], [(0, laser(rays=1, max_range=4.0))])
    noisy = np.concatenate(read(finder, [(7.45, 2.0, 0.0)], [(0, spec)] * 4000))
    errors = noisy - clean[0]
    assert errors.mean() == pytest.approx(0.05, abs=0.002)
    assert errors.std() == pytest.approx(0.02, rel=0.06)


def test_noise_is_repeatable_with_the_seed(finder):
    spec = laser(Noise(mean=0.0, std=0.05))
    first, = read(finder, [(2.0, 1.5, 0.3)], [(0, spec)], seed=7)
    again, = read(finder, [(2.0, 1.5, 0.3)], [(0, spec)], seed=7)
    other, = read(finder, [(2.0, 1.5, 0.3)], [(0, spec)], seed=8)
    assert np.array_equal(first, again) and not np.array_equal(first, other)


def test_laser_sees_other_robots_but_not_its_own(finder):
    poses = [(2.0, 2.0, 0.0), (3.0, 2.0, 0.0)]
    ranges, = read(finder, poses, [(0, laser(rays=1))], radii=[0.2, 0.3])
    assert ranges[0] == pytest.approx(1.0 - 0.3)


def test_returns_beyond_or_short_of_the_range_follow_rep_117(finder):
    beyond, = read(finder, [(2.0, 2.0, 0.0)], [(0, laser(rays=1, max_range=1.0))])
    assert np.isposinf(beyond[0])
    poses = [(2.0, 2.0, 0.0), (2.45, 2.0, 0.0)]
    close, = read(finder, poses, [(0, laser(rays=1, min_range=0.1))], radii=[0.2, 0.2])
    assert close[0] == pytest.approx(0.25)
    too_close, = read(finder, poses, [(0, laser(rays=1, min_range=0.3))], radii=[0.2, 0.2])
    assert np.isneginf(too_close[0])


def test_sonar_reads_the_nearest_return_in_its_cone(finder):
    off_axis = math.radians(30)
    poses = [(2.0, 2.0, 0.0), (2.0 + math.cos(off_axis), 2.0 + math.sin(off_axis), 0.0)]
    reading, = read(finder, poses, [(0, sonar(cone=0.87))])
    assert reading == pytest.approx(1.0 - 0.2, abs=0.03)
    narrow, = read(finder, poses, [(0, sonar(cone=0.3))])
    assert narrow > 2.5 or np.isposinf(narrow)


def test_many_sensors_of_many_robots_in_one_batch(finder):
    poses = [(2.0, 2.0, 0.0), (5.0, 2.0, math.pi / 2), (8.0, 1.0, math.pi)]
    jobs = [(index, spec) for index in range(3) for spec in (laser(), sonar())]
    readings = read(finder, poses, jobs)
    assert [np.size(reading) for reading in readings] == [667, 1] * 3
    single = read(finder, poses, [(1, laser())])[0]
    assert np.array_equal(readings[2], single)
