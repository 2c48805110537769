"""The simulation core: robots by name, held commands, sensor schedules, lockstep answers."""

from dataclasses import replace
import math

from map_fixtures import walled_room, write_map
import pytest
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.robot_description import (LaserSpec, Noise, RobotDescription, RobotEntry,
                                              SonarSpec)
from stdr_lite.core.simulation import CommandOutcome, RequestError, Simulation, SimulationSettings
from stdr_lite.core.world import PlacementError

PLAIN = RobotDescription(0.2, (0.0, 0.0, 0.0))
LASER = LaserSpec('laser_0', (0.1, 0.0, 0.0), -1.0, 1.0, 0.05, 4.0, 5, 10.0, Noise())
SONAR = SonarSpec('sonar_0', (0.1, 0.0, 0.0), 0.5, 0.1, 3.0, 5.0, Noise())
SENSING = RobotDescription(0.2, (0.0, 0.0, 0.0), (LASER,), (SONAR,))


@pytest.fixture
def room(tmp_path):
    """Give an empty 10 m x 4 m room."""
    return load_map(write_map(tmp_path, walled_room(200, 80)))


def robot(name, x, y=2.0, theta=0.0, description=PLAIN):
    return RobotEntry(name, description, (x, y, theta))


def test_robots_are_known_by_name_and_keep_their_state_when_others_leave(room):
    simulation = Simulation(room, robots=[robot('a', 2.0), robot('b', 4.0), robot('c', 6.0)])
    simulation.command('c', 0.5, 0.0)
    simulation.remove_robot('a')
    assert simulation.names == ['b', 'c']
    simulation.step()
    assert simulation.pose('b') == (4.0, 2.0, 0.0)
    assert simulation.pose('c')[0] == pytest.approx(6.0 + 0.5 * 0.02)
    assert simulation.applied_velocity('c') == (0.5, 0.0)
    assert simulation.applied_velocity('b') == (0.0, 0.0)
    assert 'a' not in simulation and simulation.default_name() == 'robot0'


@pytest.mark.parametrize('entry, error, message', [
    (robot('b', 2.3), PlacementError, 'overlaps a'),
    (robot('b', 0.1), PlacementError, 'touches a wall'),
    (robot('b', 40.0), PlacementError, 'off the map'),
    (robot('a', 8.0), RequestError, 'exists already'),
    (robot('robé', 8.0), RequestError, 'must be a ROS name'),
    (robot('b', 8.0, description=RobotDescription(0.2, (0, 0, 0),
                                                  (replace(LASER, frequency=80.0),))),
     RequestError, 'laser_0 reads at 80 Hz, faster than the simulation steps'),
])
def test_a_refused_robot_changes_nothing(room, entry, error, message):
    simulation = Simulation(room, robots=[robot('a', 2.0)])
    with pytest.raises(error, match=message):
        simulation.add_robot(entry)
    assert simulation.names == ['a']
    simulation.command('a', 1.0, 0.0)
    simulation.step()
    assert simulation.pose('a')[0] == pytest.approx(2.02)


def test_teleport_is_refused_whole_onto_another_robot(room):
    simulation = Simulation(room, robots=[robot('a', 2.0), robot('b', 5.0)])
    with pytest.raises(PlacementError, match='overlaps a'):
        simulation.teleport('b', (2.2, 2.0, 1.0))
    assert simulation.pose('b') == (5.0, 2.0, 0.0)
    simulation.teleport('b', (7.0, 3.0, 1.0))
    assert simulation.pose('b') == (7.0, 3.0, 1.0)


def test_unknown_names_are_request_errors(room):
    simulation = Simulation(room)
    for call in (lambda: simulation.remove_robot('x'), lambda: simulation.pose('x'),
                 lambda: simulation.command('x', 0.0, 0.0)):
        with pytest.raises(RequestError, match="no robot named 'x'"):
            call()


def test_commands_are_held_clamped_or_ignored(room):
    settings = SimulationSettings(rate_hz=10.0, max_linear_speed=1.0, max_angular_speed=2.0)
    simulation = Simulation(room, settings, [robot('a', 2.0)])
    assert simulation.command('a', 0.5, 0.0) is CommandOutcome.APPLIED
    assert simulation.command('a', math.inf, 0.0) is CommandOutcome.IGNORED
    simulation.step()
    assert simulation.applied_velocity('a') == (0.5, 0.0)
    assert simulation.command('a', 5.0, -9.0) is CommandOutcome.CLAMPED
    simulation.step()
    assert simulation.applied_velocity('a') == (1.0, -2.0)
    assert simulation.sim_time == pytest.approx(0.2) and simulation.time_ns == 200_000_000


def test_a_stale_command_stops_the_robot_after_the_timeout(room):
    simulation = Simulation(room, SimulationSettings(rate_hz=10.0, cmd_vel_timeout=0.25),
                            [robot('a', 2.0)])
    simulation.command('a', 0.5, 0.0)
    moving = []
    for _ in range(5):
        simulation.step()
        moving.append(simulation.applied_velocity('a')[0] > 0.0)
    assert moving == [True, True, True, False, False]


def test_sensors_fall_due_at_their_own_frequency(room):
    simulation = Simulation(room, SimulationSettings(rate_hz=50.0),
                            [robot('a', 2.0, description=SENSING)])
    due = {}
    for _ in range(50):
        simulation.step()
        for name, spec in simulation.due_sensors():
            due.setdefault(spec.frame_id, []).append(simulation.step_count)
    assert due == {'laser_0': list(range(5, 51, 5)), 'sonar_0': list(range(10, 51, 10))}


def test_readings_see_walls_and_other_robots(room):
    simulation = Simulation(room, robots=[robot('a', 2.0, description=SENSING),
                                          robot('b', 3.5)])
    scan, sonar = simulation.read_sensors([('a', LASER), ('a', SONAR)])
    assert scan[2] == pytest.approx(3.5 - 0.2 - 2.1, abs=1e-6)
    assert sonar == pytest.approx(3.5 - 0.2 - 2.1, abs=1e-6)


def test_lockstep_waits_for_every_robot_once(room):
    simulation = Simulation(room, robots=[robot('a', 2.0), robot('b', 5.0)])
    assert not simulation.awaiting_answers
    simulation.expect_answers()
    assert simulation.answer('a') and simulation.awaiting_answers
    assert not simulation.answer('a')
    simulation.remove_robot('b')
    assert not simulation.awaiting_answers
