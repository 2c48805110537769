"""Odometry: exact without noise, and a drift whose covariance says how large it really is."""

import math

from map_fixtures import walled_room, write_map
import numpy as np
import pytest

from simple_robot_control.occupancy_map import load_map
from simple_robot_control.pose import compose
from stdr_lite.core.odometry import Odometry
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.setting_values import OdometryNoise
from stdr_lite.core.simulation import Simulation, SimulationSettings
from stdr_lite.core.state import StateTable

NOISE = OdometryNoise(distance=0.05, turn=0.05, heading_per_distance=0.02)


@pytest.fixture
def room(tmp_path):
    """Give an empty 10 m x 4 m room."""
    return load_map(write_map(tmp_path, walled_room(200, 80)))


def simulation_in(room, noise=OdometryNoise(), seed=0, **settings):
    robot = RobotEntry('robot0', RobotDescription(0.2, (0, 0, 0)), (2.0, 2.0, 0.0))
    return Simulation(room, SimulationSettings(odometry_noise=noise, odom_seed=seed, **settings),
                      [robot])


def drive(simulation, linear, angular, steps):
    simulation.command('robot0', linear, angular)
    for _ in range(steps):
        simulation.step()


def test_without_noise_the_odometry_is_the_true_pose_whatever_happens(room):
    simulation = simulation_in(room)
    drive(simulation, 0.5, 0.3, 100)
    simulation.teleport('robot0', (6.0, 3.0, 1.0))
    reading = simulation.odometry('robot0')
    assert reading.pose == simulation.pose('robot0') == (6.0, 3.0, 1.0)
    assert reading.velocity == (0.5, 0.0, 0.3)
    assert not reading.pose_covariance.any() and reading.velocity_variance == (0.0, 0.0, 0.0)
    assert simulation.map_to_odom('robot0') == (0.0, 0.0, 0.0)


def test_map_to_odom_to_base_link_is_the_true_pose_under_noise_and_teleports(room):
    simulation = simulation_in(room, NOISE)
    for step in range(6):
        drive(simulation, 0.4, 0.5 * (-1) ** step, 40)
        if step == 3:
            simulation.teleport('robot0', (7.0, 2.5, -2.0))
        truth = compose(simulation.map_to_odom('robot0'), simulation.odometry('robot0').pose)
        assert truth == pytest.approx(simulation.pose('robot0'), abs=1e-9)
    assert simulation.odometry('robot0').pose != pytest.approx(simulation.pose('robot0'))


def test_seeded_noise_repeats_and_other_seeds_differ(room):
    runs = []
    for seed in (3, 3, 4):
        simulation = simulation_in(room, NOISE, seed)
        drive(simulation, 0.5, 0.2, 150)
        runs.append(simulation.odometry('robot0').pose)
    assert runs[0] == runs[1] and runs[0] != runs[2]


def test_covariance_grows_while_driving_and_holds_while_standing(room):
    simulation = simulation_in(room, NOISE)
    spreads = []
    for _ in range(5):
        drive(simulation, 0.5, 0.4, 20)
        spreads.append(np.trace(simulation.odometry('robot0').pose_covariance))
    drive(simulation, 0.0, 0.0, 20)
    reading = simulation.odometry('robot0')
    assert spreads == sorted(spreads) and spreads[0] > 0.0
    assert np.trace(reading.pose_covariance) == pytest.approx(spreads[-1])
    assert np.all(np.linalg.eigvalsh(reading.pose_covariance) > 0.0)
    assert reading.velocity_variance == (0.0, 0.0, 0.0)


@pytest.mark.parametrize('dt, lateral', [(0.01, 0.0), (0.1, 0.0), (0.05, 0.3)])
def test_the_spread_is_what_the_covariance_says_at_any_step_rate(dt, lateral):
    """Two thousand robots drive 2 m along a gentle curve; compare their scatter with P."""
    robots = 2000
    state = StateTable.of_bodies([(0.0, 0.0, 0.0)] * robots)
    odometry = Odometry(state, NOISE, seed=7)
    state.applied[:] = (0.5, lateral, 0.2)
    steps = round(4.0 / dt)
    for _ in range(steps):
        odometry.advance(dt)
    predicted = odometry.reading(0).pose_covariance
    observed = np.cov(state.odometry_pose.T)
    assert np.sqrt(np.diag(observed)) == pytest.approx(np.sqrt(np.diag(predicted)), rel=0.1)
    heading_std = math.sqrt(NOISE.turn ** 2 * 0.8
                            + NOISE.heading_per_distance ** 2 * (2.0 + 4.0 * lateral))
    assert math.sqrt(predicted[2, 2]) == pytest.approx(heading_std, rel=1e-6)


def test_odometry_is_due_at_its_own_rate(room):
    simulation = simulation_in(room, rate_hz=50.0, odom_rate_hz=10.0)
    due = [simulation.odometry_due()]
    for _ in range(20):
        simulation.step()
        due.append(simulation.odometry_due())
    assert [step for step, is_due in enumerate(due) if is_due] == [0, 5, 10, 15, 20]
