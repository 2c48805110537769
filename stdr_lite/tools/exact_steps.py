"""
Hold a command for an exact number of simulation steps, through simulation_interfaces.

A stop published when the odometry shows the duration elapsed lands a step or more late on a
free-running simulator under load. Handing the duration to the simulator instead leaves no
race: pause, send the command and have it received, take duration * rate_hz steps with the
simulate_steps action (paced as usual, so the motion looks as it would), send the stop, have
it received, and play on. Used from a worker thread while an executor spins the node.
"""

import threading
import time

from rcl_interfaces.msg import ParameterType
from rclpy.action import ActionClient
from rclpy.parameter_client import AsyncParameterClient
from simulation_interfaces.action import SimulateSteps
from simulation_interfaces.msg import Result, SimulationState
from simulation_interfaces.srv import SetSimulationState

# How long to wait for the simulator's services to show, once it publishes odometry.
DISCOVERY_PATIENCE = 3.0


class SimulatorUnavailable(Exception):
    """The simulator offers no stepping API, or stopped answering it."""


class ExactSteps:
    """The simulator's pause, steps and play, as blocking calls that give up when it is gone."""

    def __init__(self, node, simulator, patience):
        self._patience = patience
        self._state = node.create_client(SetSimulationState, f'{simulator}/set_simulation_state')
        self._steps = ActionClient(node, SimulateSteps, f'{simulator}/simulate_steps')
        self._parameters = AsyncParameterClient(node, simulator)
        self.rate_hz = None

    def connect(self) -> bool:
        """Wait briefly for the API and read the step rate; return whether it is there."""
        deadline = time.monotonic() + DISCOVERY_PATIENCE
        while not (self._state.service_is_ready() and self._steps.server_is_ready()
                   and self._parameters.services_are_ready()):
            if time.monotonic() > deadline:
                return False
            time.sleep(0.01)
        answer = self._wait(self._parameters.get_parameters(['rate_hz']))
        value = answer.values[0] if answer.values else None
        if value is None or value.type != ParameterType.PARAMETER_DOUBLE:
            return False
        self.rate_hz = value.double_value
        return True

    def pause(self) -> bool:
        """Pause the simulation; return whether it was playing."""
        return self._set(SimulationState.STATE_PAUSED)

    def play(self) -> None:
        self._set(SimulationState.STATE_PLAYING)

    def take(self, steps: int) -> None:
        """Take steps (paused), paced as the simulator paces its loop."""
        handle = self._wait(self._steps.send_goal_async(SimulateSteps.Goal(steps=steps)))
        if not handle.accepted:
            raise SimulatorUnavailable('simulate_steps refused the goal')
        # The action's time is the simulation's: allow for a slow real_time_factor.
        outcome = self._wait(handle.get_result_async(), steps / self.rate_hz * 100.0)
        if outcome.result.result.result != Result.RESULT_OK:
            raise SimulatorUnavailable(f'simulate_steps: {outcome.result.result.error_message}')

    def _set(self, state):
        request = SetSimulationState.Request()
        request.state.state = state
        answer = self._wait(self._state.call_async(request)).result
        if answer.result == SetSimulationState.Response.ALREADY_IN_TARGET_STATE:
            return False
        if answer.result != Result.RESULT_OK:
            raise SimulatorUnavailable(f'set_simulation_state: {answer.error_message}')
        return True

    def _wait(self, future, timeout=None):
        arrived = threading.Event()
        future.add_done_callback(lambda _: arrived.set())
        if not arrived.wait(self._patience + (timeout or 0.0)):
            raise SimulatorUnavailable('the simulator stopped answering')
        return future.result()
