"""The simulation core: robots by name, held commands, sensor schedules."""

from dataclasses import replace
import math

from map_fixtures import walled_room, write_map
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.bodies import PlacementError
from stdr_lite.core.robot_description import (LaserSpec, Noise, parse_robot_text,
                                              RobotDescription, RobotEntry, SonarSpec)
from stdr_lite.core.simulation import CommandOutcome, RequestError, Simulation, SimulationSettings

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
    simulation.remove('a')
    assert simulation.names == ['b', 'c']
    simulation.step()
    assert simulation.pose('b') == (4.0, 2.0, 0.0)
    assert simulation.pose('c')[0] == pytest.approx(6.0 + 0.5 * 0.02)
    assert simulation.applied_velocity('c') == (0.5, 0.0, 0.0)
    assert simulation.applied_velocity('b') == (0.0, 0.0, 0.0)
    assert 'a' not in simulation and simulation.default_name() == 'robot0'


@pytest.mark.parametrize('entry, error, message', [
    (robot('b', 2.3), PlacementError, 'overlaps a'),
    (robot('b', 0.1), PlacementError, 'touches a wall'),
    (robot('b', 40.0), PlacementError, 'off the map'),
    (robot('a', 8.0), RequestError, 'an entity named a exists already'),
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
    for call in (lambda: simulation.remove('x'), lambda: simulation.pose('x'),
                 lambda: simulation.command('x', 0.0, 0.0)):
        with pytest.raises(RequestError, match="no entity named 'x'"):
            call()


def test_commands_are_held_clamped_or_ignored(room):
    settings = SimulationSettings(rate_hz=10.0, max_linear_speed=1.0, max_angular_speed=2.0)
    simulation = Simulation(room, settings, [robot('a', 2.0)])
    assert simulation.command('a', 0.5, 0.0) is CommandOutcome.APPLIED
    assert simulation.command('a', math.inf, 0.0) is CommandOutcome.IGNORED
    simulation.step()
    assert simulation.applied_velocity('a') == (0.5, 0.0, 0.0)
    assert simulation.command('a', 5.0, -9.0) is CommandOutcome.CLAMPED
    simulation.step()
    assert simulation.applied_velocity('a') == (1.0, 0.0, -2.0)
    assert simulation.command('a', 0.5, 0.0, lateral=0.5) is CommandOutcome.NOT_OMNI
    simulation.step()
    assert simulation.applied_velocity('a') == (0.5, 0.0, 0.0)
    assert simulation.sim_time == pytest.approx(0.3) and simulation.time_ns == 300_000_000


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


def test_each_sensor_keeps_its_own_phase_whoever_comes_and_goes(room):
    """Sensors share schedules by reading times: a robot added later reads in its own phase."""
    simulation = Simulation(room, SimulationSettings(rate_hz=50.0),
                            [robot('a', 2.0, description=SENSING)])
    due = {}
    for step in range(1, 61):
        if step == 8:
            simulation.add_robot(robot('b', 4.0, description=SENSING))
        if step == 23:
            simulation.add_robot(robot('c', 6.0, description=SENSING))
        if step == 40:
            simulation.remove('b')
        simulation.step()
        for name, spec in simulation.due_sensors(wanted=lambda name: name != 'c' or step > 30):
            due.setdefault((name, spec.frame_id), []).append(simulation.step_count)
    assert due[('a', 'laser_0')] == list(range(5, 61, 5))
    assert due[('b', 'laser_0')] == list(range(12, 40, 5))
    assert due[('b', 'sonar_0')] == list(range(17, 40, 10))
    assert due[('c', 'laser_0')] == list(range(32, 61, 5))
    assert due[('c', 'sonar_0')] == [32, 42, 52]
    simulation.reset(state=False, spawned=False)
    simulation.step()
    assert simulation.due_sensors() == []


def test_readings_see_walls_and_other_robots(room):
    simulation = Simulation(room, robots=[robot('a', 2.0, description=SENSING),
                                          robot('b', 3.5)])
    scan, sonar = simulation.read_sensors([('a', LASER), ('a', SONAR)])
    assert scan[2] == pytest.approx(3.5 - 0.2 - 2.1, abs=1e-6)
    assert sonar == pytest.approx(3.5 - 0.2 - 2.1, abs=1e-6)


def test_obstacles_block_robots_and_are_seen_by_sensors(room):
    simulation = Simulation(room, robots=[robot('a', 2.0, description=SENSING)])
    simulation.add_obstacle('rock', 0.3, (3.0, 2.0, 0.0))
    scan, _ = simulation.read_sensors([('a', LASER), ('a', SONAR)])
    assert scan[2] == pytest.approx(3.0 - 0.3 - 2.1, abs=1e-6)
    simulation.command('a', 1.0, 0.0)
    for _ in range(100):
        simulation.step()
    assert simulation.pose('a')[0] == pytest.approx(2.5, abs=0.03)
    assert simulation.pose('rock') == (3.0, 2.0, 0.0)


def test_a_robot_stalls_only_while_a_step_of_its_own_is_refused(room):
    simulation = Simulation(room, robots=[robot('a', 9.0), robot('b', 5.0), robot('c', 2.0)])
    simulation.add_obstacle('rock', 0.3, (5.6, 2.0, 0.0))
    simulation.command('a', 1.0, 0.0)
    simulation.command('b', 1.0, 0.0)
    simulation.command('c', 0.0, 1.0)
    stalls = []
    for _ in range(60):
        simulation.step()
        stalls.append([simulation.stalled(name) for name in ('a', 'b', 'c', 'rock')])
    assert stalls[0] == [False, False, False, False]
    assert stalls[-1] == [True, True, False, False], 'a at the wall, b at the rock'
    simulation.command('a', -1.0, 0.0)
    simulation.step()
    assert not simulation.stalled('a'), 'a robot at a wall may drive away from it'
    simulation.remove('a')
    assert simulation.stalled('b')


def test_a_moving_obstacle_slides_until_something_stops_it(room):
    simulation = Simulation(room, robots=[robot('a', 7.0)])
    simulation.add_obstacle('ball', 0.2, (3.0, 2.0, 0.0), moving=True)
    simulation.set_velocity('ball', 0.5, 0.0, 1.0)
    simulation.step()
    assert simulation.pose('ball') == pytest.approx((3.01, 2.0, 0.02))
    assert simulation.velocity('ball') == pytest.approx((0.5, 0.0, 1.0))
    for _ in range(600):
        simulation.step()
    assert simulation.pose('ball')[0] == pytest.approx(7.0 - 0.4, abs=0.02)
    assert simulation.velocity('ball') == (0.0, 0.0, 0.0)
    assert simulation.pose('a') == (7.0, 2.0, 0.0)


@pytest.mark.parametrize('name, velocity, message', [
    ('a', (0.0, 0.5, 0.0), 'unicycle'),
    ('rock', (0.1, 0.0, 0.0), 'static obstacle does not move'),
    ('ball', (500.0, 0.0, 0.0), 'exceeds the limits'),
    ('ball', (float('nan'), 0.0, 0.0), 'must be finite'),
])
def test_a_refused_state_changes_neither_pose_nor_velocity(room, name, velocity, message):
    simulation = Simulation(room, robots=[robot('a', 2.0)])
    simulation.add_obstacle('rock', 0.3, (5.0, 2.0, 0.0))
    simulation.add_obstacle('ball', 0.3, (7.0, 2.0, 0.0), moving=True)
    before = simulation.pose(name)
    with pytest.raises(RequestError, match=message):
        simulation.set_state(name, (8.5, 3.0, 0.0), velocity)
    simulation.step()
    assert simulation.pose(name) == before


def test_a_robot_set_moving_along_its_new_heading_drives_there(room):
    simulation = Simulation(room, robots=[robot('a', 2.0)])
    simulation.set_state('a', (3.0, 2.0, math.pi / 2), (0.0, 0.5, 0.0))
    simulation.step()
    assert simulation.pose('a') == pytest.approx((3.0, 2.01, math.pi / 2))


def test_reset_by_scope(room):
    simulation = Simulation(room, robots=[robot('a', 2.0)])
    simulation.add_obstacle('rock', 0.3, (5.0, 3.0, 0.0))
    simulation.command('a', 0.5, 0.0)
    for _ in range(10):
        simulation.step()
    simulation.reset(time=False, state=False, spawned=True)
    assert simulation.names == ['a'] and simulation.step_count == 10
    assert simulation.pose('a')[0] == pytest.approx(2.1)
    simulation.reset(time=True, state=False, spawned=False)
    assert simulation.step_count == 0 and simulation.pose('a')[0] == pytest.approx(2.1)
    simulation.reset(time=False, state=True, spawned=False)
    assert simulation.pose('a') == (2.0, 2.0, 0.0)
    simulation.step()
    assert simulation.applied_velocity('a') == (0.0, 0.0, 0.0)


def test_a_reset_that_cannot_put_everyone_back_changes_nothing(room):
    simulation = Simulation(room, robots=[robot('a', 2.0)])
    simulation.teleport('a', (6.0, 2.0, 0.0))
    simulation.add_obstacle('rock', 0.3, (2.0, 2.0, 0.0))
    with pytest.raises(PlacementError, match='rock cannot stand at its start pose: .* overlaps a'):
        simulation.reset(time=True, state=True, spawned=False)
    assert simulation.names == ['a', 'rock'] and simulation.pose('a') == (6.0, 2.0, 0.0)


def test_a_new_map_keeps_the_start_robots_or_refuses_whole(room, tmp_path):
    simulation = Simulation(room, robots=[robot('a', 2.0)])
    simulation.add_obstacle('rock', 0.3, (5.0, 3.0, 0.0))
    for _ in range(5):
        simulation.step()
    small = load_map(write_map(tmp_path, walled_room(30, 30), name='small'))
    with pytest.raises(PlacementError, match='a cannot stand at its start pose'):
        simulation.load_map(small)
    assert simulation.names == ['a', 'rock'] and simulation.step_count == 5
    other = load_map(write_map(tmp_path, walled_room(100, 100), name='other'))
    simulation.load_map(other)
    assert simulation.names == ['a'] and simulation.step_count == 0
    assert simulation.occupancy_map is other and simulation.pose('a') == (2.0, 2.0, 0.0)


# A Hokuyo laser as STDR's own files describe it (mean 0.5 m, std 0.05 m), in STDR's XML.
STDR_HOKUYO_ROBOT = """<robot><robot_specifications>
  <footprint><footprint_specifications><radius>0.2</radius></footprint_specifications></footprint>
  <laser><laser_specifications>
    <max_angle>1</max_angle><min_angle>-1</min_angle><max_range>4</max_range>
    <min_range>0.05</min_range><num_rays>5</num_rays><frequency>10</frequency>
    <pose><x>0.1</x><y>0</y><theta>0</theta></pose>
    <noise><noise_specifications><noise_mean>0.5</noise_mean><noise_std>0.05</noise_std>
    </noise_specifications></noise>
  </laser_specifications></laser>
</robot_specifications></robot>"""


def first_laser_reading(room, settings, description):
    simulation = Simulation(room, settings, [robot('a', 2.0, description=description)])
    readings, = simulation.read_sensors([('a', simulation.robot('a').sensors[0].spec)])
    return readings


@pytest.mark.parametrize('mode, stdr_noisy, flat_noisy', [
    ('auto', False, True), ('all', True, True), ('none', False, False)])
def test_stdr_files_read_as_under_stdr_unless_all_noise_is_asked(
        room, mode, stdr_noisy, flat_noisy):
    stdr_file = parse_robot_text(STDR_HOKUYO_ROBOT, 'hokuyo_robot.xml')
    assert stdr_file.stdr_layout and stdr_file.lasers[0].noise == Noise(0.5, 0.05)
    flat_file = replace(stdr_file, stdr_layout=False)
    exact = Simulation(room, robots=[robot('a', 2.0, description=SENSING)])
    clean, _ = exact.read_sensors([('a', LASER), ('a', SONAR)])
    returns = np.isfinite(clean)
    assert returns.any()
    settings = SimulationSettings(sensor_noise=mode)
    for description, noisy in ((stdr_file, stdr_noisy), (flat_file, flat_noisy)):
        readings = first_laser_reading(room, settings, description)
        if noisy:
            assert (readings[returns] - clean[returns]) == pytest.approx(0.5, abs=0.25)
            assert settings.sensor_noise_note(description) == (
                'sensor noise as its file describes')
        else:
            assert list(readings) == list(clean)
            assert "file's sensor noise not applied" in settings.sensor_noise_note(description)


def test_the_sensor_noise_mode_is_checked():
    with pytest.raises(ValueError, match='sensor_noise must be one of auto, all, none'):
        SimulationSettings(sensor_noise=True)


def test_a_world_with_no_entity_steps_and_keeps_its_clock(room):
    simulation = Simulation(room, robots=[robot('a', 2.0, description=SENSING)])
    simulation.remove('a')
    for _ in range(10):
        simulation.step()
    assert simulation.names == [] and simulation.sim_time == pytest.approx(0.2)
    assert simulation.odometry_due()
    simulation.add_robot(robot('b', 3.0))
    simulation.command('b', 1.0, 0.0)
    simulation.step()
    assert simulation.pose('b')[0] == pytest.approx(3.02)
