"""Robots bump into each other: the one that moves into another is stopped short of it."""

import math

from map_fixtures import walled_room, write_map
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.bodies import Bodies, PlacementError


@pytest.fixture
def world(tmp_path):
    """Give an empty 10 m x 4 m room."""
    return Bodies(load_map(write_map(tmp_path, walled_room(200, 80))), max_radius=0.3)


def gap(world, first=0, second=1):
    return (math.dist(world.poses[first, :2], world.poses[second, :2])
            - world.radii[first] - world.radii[second])


def test_head_on_robots_stop_short_of_each_other(world):
    world.add_body((3.0, 2.0, 0.0), 0.2)
    world.add_body((7.0, 2.0, math.pi), 0.25)
    for _ in range(200):
        moved = world.step([0.5, 0.5], [0.0, 0.0], 0.05)
        assert gap(world) >= 0.0
    assert moved.tolist() == [False, False]
    assert gap(world) < 2 * 0.5 * 0.05


def test_robot_driving_into_a_standing_one_is_stopped_and_the_other_is_not_pushed(world):
    world.add_body((3.0, 2.0, 0.0), 0.2)
    world.add_body((4.0, 2.0, 0.0), 0.2)
    for _ in range(100):
        world.step([1.0, 0.0], [0.0, 0.0], 0.05)
    assert world.poses[1].tolist() == [4.0, 2.0, 0.0]
    assert 0.0 <= gap(world) < 0.05


def test_robot_leaving_one_that_follows_is_not_blamed(world):
    world.add_body((3.0, 2.0, 0.0), 0.2)
    world.add_body((3.41, 2.0, 0.0), 0.2)
    assert world.step([1.0, 0.5], [0.0, 0.0], 0.1).tolist() == [False, True]
    assert gap(world) >= 0.0


def test_robots_in_contact_may_turn_and_part(world):
    world.add_body((3.0, 2.0, 0.0), 0.2)
    world.add_body((3.41, 2.0, math.pi), 0.2)
    assert world.step([0.0, 0.0], [1.0, 1.0], 0.1).tolist() == [True, True]
    assert world.step([-0.5, -0.5], [0.0, 0.0], 0.1).tolist() == [True, True]
    assert gap(world) > 0.0


def test_no_robot_can_be_placed_or_teleported_onto_another(world):
    world.add_body((3.0, 2.0, 0.0), 0.2)
    world.add_body((5.0, 2.0, 0.0), 0.2)
    with pytest.raises(PlacementError, match='overlaps body 0'):
        world.add_body((3.3, 2.1, 0.0), 0.2)
    with pytest.raises(PlacementError, match='overlaps body 0'):
        world.move_body(1, (3.2, 2.0, 1.0))
    assert world.poses[1].tolist() == [5.0, 2.0, 0.0]
    world.move_body(1, (6.0, 3.0, 1.0))
    assert world.poses[1].tolist() == [6.0, 3.0, 1.0]
    world.move_body(1, (6.05, 3.0, 1.0))
    with pytest.raises(PlacementError, match='touches a wall'):
        world.move_body(1, (9.9, 3.0, 1.0))


def test_removing_a_robot_renumbers_those_after_it(world):
    for x in (2.0, 4.0, 6.0):
        world.add_body((x, 2.0, 0.0), 0.2)
    world.remove_body(1)
    assert world.body_count == 2
    assert world.poses[:, 0].tolist() == [2.0, 6.0]
    world.add_body((4.0, 2.0, 0.0), 0.2)


def test_a_crowd_never_overlaps(world):
    rng = np.random.default_rng(5)
    while world.body_count < 40:
        try:
            world.add_body((rng.uniform(0.5, 9.5), rng.uniform(0.5, 3.5), rng.uniform(-3, 3)),
                           0.2)
        except PlacementError:
            continue
    for _ in range(200):
        world.step(rng.uniform(-1.0, 1.0, 40), rng.uniform(-2.0, 2.0, 40), 0.05)
        centres = world.poses[:, :2]
        distances = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1))
        np.fill_diagonal(distances, np.inf)
        assert distances.min() >= 0.4 - 1e-9


def test_a_step_kilometres_long_is_checked_along_its_whole_path(world):
    world.add_body((3.0, 2.0, 0.0), 0.2)
    assert world.step([10000.0], [0.0], 1.0).tolist() == [False]
    assert world.poses[0].tolist() == [3.0, 2.0, 0.0]
