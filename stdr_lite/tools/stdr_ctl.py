"""
stdr_ctl: the standard simulation services of stdr_lite from a shell, without ros2cli.

Each command (ctl_commands.py) is one request (two for set-velocity) to the simulator's
simulation_interfaces services or its SimulateSteps action. The answer is printed; the exit
code is 0 for RESULT_OK, 1 for a refusal or no simulator answering, 2 for bad arguments. On a
Jazzy machine `ros2 service call /stdr_lite/<service> ...` does the same (see the README).
"""

import sys
import uuid

from action_msgs.msg import GoalInfo, GoalStatus, GoalStatusArray
from action_msgs.srv import CancelGoal
from rclpy.clock import Clock, ClockType
from rclpy.qos import qos_profile_action_status_default
from rclpy.task import Future
from simple_robot_control.command_line import keep_stdout_for_answers
from simple_robot_control.exit_codes import EXIT_FAILED, EXIT_OK
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import run
from simulation_interfaces.msg import Result
from stdr_lite.node.results import SERVICE_QOS
from stdr_lite.tools.ctl_commands import build_arguments, COMMANDS, constant_names
from unique_identifier_msgs.msg import UUID

POLL_PERIOD = 0.05
ENDED = (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_CANCELED, GoalStatus.STATUS_ABORTED)


class StdrCtl(GuardedNode):
    """Sends one command's requests in turn and finishes with the exit code of the answer."""

    def __init__(self, options, write=print, complain=None, **kwargs):
        super().__init__('stdr_ctl', **kwargs)
        self.finished = Future()
        self._options, self._write = options, write
        self._complain = complain or (lambda line: print(line, file=sys.stderr))
        self._clock = Clock(clock_type=ClockType.STEADY_TIME)
        self._call = self._client = self._answer = self._goal = None
        self._deadline = 0
        self._results = self._cancel = self._goal_status = None
        self._accepted_goal = False
        self.create_timer(POLL_PERIOD, self._check, clock=self._clock)
        self._start(COMMANDS[options.command][2](options))

    def _name(self, service):
        return f'{self._options.simulator.rstrip("/")}/{service}'

    def _start(self, call):
        """
        Make the clients of a call: a service's, or the three services of the action.

        The action is driven through its services and status topic directly, so that a goal
        whose acceptance reply was lost is still followed: the status topic shows it.
        """
        self._call, self._answer, self._accepted_goal = call, None, False
        name = self._name(call.service)
        if call.is_action:
            action = call.kind.Impl
            self._client = self.create_client(action.SendGoalService, f'{name}/_action/send_goal',
                                              qos_profile=SERVICE_QOS)
            self._results = self.create_client(action.GetResultService,
                                               f'{name}/_action/get_result',
                                               qos_profile=SERVICE_QOS)
            self._cancel = self.create_client(CancelGoal, f'{name}/_action/cancel_goal',
                                              qos_profile=SERVICE_QOS)
            self.create_subscription(GoalStatusArray, f'{name}/_action/status',
                                     self._on_goal_status, qos_profile_action_status_default)
        else:
            self._client = self.create_client(call.kind, name, qos_profile=SERVICE_QOS)
        self._deadline = self._later()

    def _later(self):
        return self._clock.now().nanoseconds + round(self._options.timeout * 1e9)

    def _check(self):
        """Send once the simulator serves the call; give up when it or its answer is late."""
        if self._call is None or self.finished.done():
            return
        call = self._call
        if self._answer is None:
            ready = self._client.service_is_ready() and (
                not call.is_action or self._results.service_is_ready())
            if ready:
                self._send(call)
                return
        elif self._accepted_goal:
            self._follow_goal(call)
            return
        if self._clock.now().nanoseconds > self._deadline:
            name = self._name(call.service)
            self._fail(f'no answer from {name} within {self._options.timeout:g} s'
                       if self._answer else f'no simulator answering: {name} is not served '
                       '(is stdr_lite running, with this ROS_DOMAIN_ID?)')

    def _send(self, call):
        self._deadline = self._later()
        if call.is_action:
            self._goal = UUID(uuid=list(uuid.uuid4().bytes))
            request = call.kind.Impl.SendGoalService.Request(
                goal_id=self._goal, goal=call.kind.Goal(**call.fields))
            self._answer = self._client.call_async(request)
            self._answer.add_done_callback(
                lambda sent: self._accepted(call, sent.result().accepted))
        else:
            fields = call.fields
            request = fields['request'] if 'request' in fields else call.kind.Request(**fields)
            self._answer = self._client.call_async(request)
            self._answer.add_done_callback(lambda done: self._answered(call, done.result()))

    def _on_goal_status(self, message):
        """Note our goal's status; seeing it at all means the simulator accepted it."""
        for status in message.status_list:
            if self._goal is not None and status.goal_info.goal_id == self._goal:
                first = self._goal_status is None
                self._goal_status = status.status
                if first and self._call is not None:
                    self._accepted(self._call, True)

    def _accepted(self, call, accepted):
        """Ask for the goal's result once it is known to be accepted (by reply or status)."""
        if self._call is not call or self.finished.done() or self._accepted_goal:
            return
        if not accepted:
            self._fail(f'{self._options.command} refused: the goal was rejected')
            return
        self._accepted_goal = True
        self._ask_result(call)

    def _ask_result(self, call):
        self._deadline = self._later()
        self._results.call_async(call.kind.Impl.GetResultService.Request(
            goal_id=self._goal)).add_done_callback(
            lambda done: self._answered(call, done.result().result))

    def _follow_goal(self, call):
        """
        Wait for a running goal's result however long it runs; ask again if it got lost.

        A reply can be lost while discovery is still matching its reader (seconds, on a loaded
        machine): when the goal's status says it ended and no result has come for a timeout,
        the result is asked again; the server keeps it.
        """
        if not self._results.service_is_ready():
            self._fail(f'{self._name(call.service)} went away before the goal ended')
        elif self._goal_status in ENDED and self._clock.now().nanoseconds > self._deadline:
            self._ask_result(call)

    def _answered(self, call, response):
        """
        Print the answer, or the refusal, or send the request that follows.

        GetSimulatorFeatures alone answers with no result: it cannot refuse. A second answer
        to a result asked twice is ignored.
        """
        if self._call is not call:
            return
        self._call = None
        outcome = getattr(response, 'result', Result(result=Result.RESULT_OK))
        code = outcome.result
        if code != Result.RESULT_OK:
            names = {**constant_names(Result), **constant_names(type(response))}
            self._fail(f'{self._options.command} refused: {names.get(code, code)}: '
                       f'{outcome.error_message}')
        elif call.then is not None:
            self._start(call.then(response))
        else:
            for line in call.report(response):
                self._write(line)
            self._finish(EXIT_OK)

    def _fail(self, line):
        self._complain(f'stdr_ctl: {line}')
        self._finish(EXIT_FAILED)

    def _finish(self, code):
        if not self.finished.done():
            self.finished.set_result(code)

    def shut_down(self) -> None:
        """Cancel a SimulateSteps goal still running (Ctrl-C), so the simulator stops it."""
        if self._call is not None and self._accepted_goal:
            self._cancel.call_async(CancelGoal.Request(goal_info=GoalInfo(goal_id=self._goal)))


def main(argv: list[str] | None = None) -> None:
    keep_stdout_for_answers()
    sys.exit(run('stdr_ctl', build_arguments(), StdrCtl, argv))


if __name__ == '__main__':
    main()
