"""The lockstep bookkeeping, all held by the Stepper: who is awaited, when it steps on."""

from map_fixtures import walled_room, write_map
import pytest
from simple_robot_control.occupancy_map import load_map
from simulation_interfaces.msg import SimulationState
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.simulation import Simulation
from stdr_lite.node.stepper import Stepper


class _Timers:
    """A node that only makes timers, none of which runs: the test calls the stepper itself."""

    def create_timer(self, period, callback, clock=None):
        return self


@pytest.fixture
def lockstep(tmp_path):
    """Give (stepper, simulation, steps taken): unpaced lockstep with robots a and b."""
    room = load_map(write_map(tmp_path, walled_room(200, 80)))
    plain = RobotDescription(0.2, (0.0, 0.0, 0.0))
    simulation = Simulation(room, robots=[RobotEntry('a', plain, (2.0, 2.0, 0.0)),
                                          RobotEntry('b', plain, (5.0, 2.0, 0.0))])
    simulation.add_obstacle('rock', 0.3, (8.0, 2.0, 0.0))
    steps = []

    def step():
        steps.append(simulation.step_count)
        simulation.step()
        return True

    stepper = Stepper(_Timers(), simulation, step, lambda: None, lambda: 0, 0.0, True)
    return stepper, simulation, steps


def test_lockstep_waits_for_every_robot_once_and_never_for_an_obstacle(lockstep):
    stepper, simulation, steps = lockstep
    stepper.start_over(new_time=True)
    stepper.answered('a')
    stepper.answered('a')
    assert steps == []
    stepper.answered('rock')
    assert steps == []
    stepper.answered('b')
    assert steps == [0]
    assert len(stepper.answer_latencies) == 2


def test_a_robot_that_goes_is_awaited_no_more(lockstep):
    stepper, simulation, steps = lockstep
    stepper.start_over(new_time=True)
    stepper.answered('a')
    simulation.remove('b')
    stepper.release()
    stepper.step_if_answered()
    assert steps == [0]


def test_an_answer_to_odometry_from_before_a_restart_of_time_steps_nothing(lockstep):
    stepper, simulation, steps = lockstep
    stepper.start_over(new_time=True)
    stepper.answered('a')
    stepper.release(everyone=True)
    stepper.answered('b')
    assert steps == []
    stepper.start_over(new_time=True)
    stepper.answered('a')
    stepper.answered('b')
    assert steps == [0]


def test_nothing_steps_while_paused_and_an_asked_step_is_taken(lockstep):
    stepper, simulation, steps = lockstep
    stepper.set_state(SimulationState.STATE_PAUSED)
    stepper.start_over(new_time=True)
    stepper.answered('a')
    stepper.answered('b')
    assert steps == []
    taken = stepper.request_step()
    assert taken.result() is True and steps == [0]
