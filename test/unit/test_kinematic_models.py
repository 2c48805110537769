"""STDR's kinematic models: omni-directional robots, motion noise, and commands as given."""

import math

from map_fixtures import walled_room, write_map
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.commands import CommandOutcome
from stdr_lite.core.motion import noisy_command
from stdr_lite.core.robot_description import Kinematic, RobotDescription, RobotEntry
from stdr_lite.core.simulation import Simulation, SimulationSettings
from stdr_lite.core.stdr_format import KINEMATIC_PARAMETERS

OMNI = RobotDescription(0.2, (0.0, 0.0, 0.0), kinematic=Kinematic('omni'))


def noisy(**parameters):
    return Kinematic('omni', tuple(parameters.get(name, 0.0) for name in KINEMATIC_PARAMETERS))


@pytest.fixture
def room(tmp_path):
    """Give an empty 10 m x 4 m room."""
    return load_map(write_map(tmp_path, walled_room(200, 80)))


def run(simulation, steps):
    for _ in range(steps):
        simulation.step()


@pytest.mark.parametrize('integrator', ['euler', 'arc'])
def test_an_omni_robot_moves_sideways_and_a_unicycle_does_not(room, integrator):
    plain = RobotDescription(0.2, (0.0, 0.0, 0.0))
    simulation = Simulation(room, SimulationSettings(rate_hz=10.0, integrator=integrator),
                            [RobotEntry('omni', OMNI, (2.0, 1.0, 0.5)),
                             RobotEntry('plain', plain, (6.0, 1.0, 0.5))])
    assert simulation.command('omni', 0.0, 0.0, lateral=0.5) is CommandOutcome.APPLIED
    assert simulation.command('plain', 0.0, 0.0, lateral=0.5) is CommandOutcome.NOT_OMNI
    run(simulation, 20)
    x, y, theta = simulation.pose('omni')
    assert (x, y) == pytest.approx((2.0 - math.sin(0.5), 1.0 + math.cos(0.5)))
    assert theta == 0.5
    assert simulation.pose('plain') == (6.0, 1.0, 0.5)
    assert simulation.applied_velocity('omni') == (0.0, 0.5, 0.0)
    assert simulation.velocity('omni') == pytest.approx((-0.5 * math.sin(0.5),
                                                         0.5 * math.cos(0.5), 0.0))


def test_an_omni_robot_turning_while_it_slides_follows_the_exact_arc(room):
    simulation = Simulation(room, SimulationSettings(rate_hz=50.0, integrator='arc'),
                            [RobotEntry('omni', OMNI, (5.0, 2.0, 0.0))])
    simulation.command('omni', 0.0, 1.0, lateral=0.5)
    run(simulation, 50)
    # Sideways at 0.5 m/s while turning at 1 rad/s: a circle of radius 0.5 about (4.5, 2).
    x, y, theta = simulation.pose('omni')
    assert math.dist((x, y), (4.5, 2.0)) == pytest.approx(0.5)
    assert theta == pytest.approx(1.0)
    assert math.atan2(y - 2.0, x - 4.5) == pytest.approx(1.0)


def test_omni_odometry_reports_the_sideways_velocity(room):
    simulation = Simulation(room, SimulationSettings(rate_hz=10.0),
                            [RobotEntry('omni', OMNI, (2.0, 2.0, 0.0))])
    simulation.command('omni', 0.3, 0.1, lateral=-0.2)
    run(simulation, 3)
    assert simulation.odometry('omni').velocity == (0.3, -0.2, 0.1)


def test_motion_noise_is_drawn_once_per_command_with_stdr_s_variances():
    parameters = noisy(a_ux_ux=0.04, a_uy_w=0.01, a_w_ux=0.09, a_g_w=0.25).parameters
    rng = np.random.default_rng(1)
    samples = np.array([noisy_command((2.0, 0.0, 1.0), parameters, rng)
                        for _ in range(20000)])
    assert samples.mean(axis=0) == pytest.approx((2.0, 0.0, 1.0), abs=0.02)
    # u_x: 0.04 * 2^2; u_y: 0.01 * 1^2; w: 0.09 * 2^2 plus the turn g: 0.25 * 1^2.
    assert samples.std(axis=0) == pytest.approx((0.4, 0.1, math.sqrt(0.36 + 0.25)), rel=0.03)
    assert noisy_command((0.0, 0.0, 0.0), parameters, rng) == (0.0, 0.0, 0.0)


def test_noisy_robots_repeat_with_their_seed_whatever_the_order_of_commands(room):
    noisy_robot = RobotDescription(0.2, (0.0, 0.0, 0.0),
                                   kinematic=noisy(a_ux_ux=0.1, a_w_w=0.1))

    def poses(seed, order):
        simulation = Simulation(room, SimulationSettings(rate_hz=10.0, motion_seed=seed),
                                [RobotEntry('a', noisy_robot, (2.0, 1.0, 0.0)),
                                 RobotEntry('b', noisy_robot, (2.0, 3.0, 0.0))])
        for _ in range(10):
            for name in order:
                simulation.command(name, 0.3, 0.2)
            run(simulation, 2)
        return simulation.pose('a'), simulation.pose('b')

    first = poses(7, 'ab')
    assert poses(7, 'ba') == first
    assert poses(8, 'ab') != first
    ideal = Simulation(room, SimulationSettings(rate_hz=10.0),
                       [RobotEntry('a', OMNI, (2.0, 1.0, 0.0))])
    for _ in range(10):
        ideal.command('a', 0.3, 0.2)
        run(ideal, 2)
    assert first[0] != ideal.pose('a')


def test_a_reset_of_time_repeats_the_motion_noise(room):
    noisy_robot = RobotDescription(0.2, (0.0, 0.0, 0.0), kinematic=noisy(a_ux_ux=0.1))
    simulation = Simulation(room, SimulationSettings(rate_hz=10.0),
                            [RobotEntry('a', noisy_robot, (2.0, 2.0, 0.0))])
    ends = []
    for _ in range(2):
        simulation.command('a', 0.5, 0.0)
        run(simulation, 10)
        ends.append(simulation.pose('a'))
        simulation.reset()
    assert ends[0] == ends[1] and ends[0][0] != 2.5


def test_lab_commands_go_unclamped_as_on_stdr(room):
    """A ROS 1 open-loop solution's 4 m/s and 4.7 rad/s are applied as given by default."""
    simulation = Simulation(room, SimulationSettings(rate_hz=10.0),
                            [RobotEntry('a', RobotDescription(0.2, (0.0, 0.0, 0.0)),
                                        (1.0, 2.0, 0.0))])
    assert simulation.command('a', 4.0, 4.7) is CommandOutcome.APPLIED
    simulation.step()
    assert simulation.applied_velocity('a') == (4.0, 0.0, 4.7)
    assert simulation.command('a', 1e6, 0.0) is CommandOutcome.SAFETY_BOUND
    clamping = Simulation(room, SimulationSettings(max_linear_speed=2.0,
                                                   max_angular_speed=math.pi),
                          [RobotEntry('a', RobotDescription(0.2, (0.0, 0.0, 0.0)),
                                      (1.0, 2.0, 0.0))])
    assert clamping.command('a', 4.0, 4.7) is CommandOutcome.CLAMPED
    clamping.step()
    assert clamping.applied_velocity('a') == (2.0, 0.0, math.pi)


def test_a_raised_safety_bound_applies_what_stdr_applies(room):
    """STDR applies 178 rad/s as given: so does stdr_lite once its safety bound is raised."""
    entry = RobotEntry('a', RobotDescription(0.2, (0.0, 0.0, 0.0)), (1.0, 2.0, 0.0))
    bounded = Simulation(room, SimulationSettings(rate_hz=10.0), [entry])
    assert bounded.command('a', 0.0, 178.0) is CommandOutcome.SAFETY_BOUND
    raised = Simulation(room, SimulationSettings(rate_hz=10.0, safety_angular_speed=200.0),
                        [entry])
    assert raised.command('a', 0.0, 178.0) is CommandOutcome.APPLIED
    raised.step()
    assert raised.pose('a')[2] == pytest.approx(math.remainder(17.8, math.tau))
    assert raised.command('a', 0.0, 201.0) is CommandOutcome.SAFETY_BOUND
