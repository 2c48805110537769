"""What every executable of this package shares: parameters, command line, and main()."""

import argparse
from dataclasses import dataclass
import os
import signal
import sys

from rcl_interfaces.msg import ParameterDescriptor, ParameterType, SetParametersResult
import rclpy
from rclpy.exceptions import InvalidParameterTypeException, ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future
from rclpy.utilities import get_default_context, remove_ros_args
from simple_robot_control.exit_codes import EXIT_BAD_INPUT, EXIT_OK
from simple_robot_control.validation import Bounds, compact, is_finite_number, ros_name_problem

SIGNAL_CHECK_PERIOD = 0.1
# Up to this many publishers and subscriptions, a node is taken down endpoint by endpoint. The
# teardown grows with the square of the count: 807 endpoints took 0.37 s here, over 1 s on a
# loaded machine; 400 take about 0.1 s.
ORDERLY_TEARDOWN_LIMIT = 400

_TYPES = {bool: ParameterType.PARAMETER_BOOL, int: ParameterType.PARAMETER_INTEGER,
          float: ParameterType.PARAMETER_DOUBLE, str: ParameterType.PARAMETER_STRING,
          list: ParameterType.PARAMETER_DOUBLE_ARRAY}


class ConfigError(Exception):
    """A configuration problem reported as one line, ending the program with exit code 2."""


@dataclass(frozen=True)
class ParameterSpec:
    """
    One node parameter: its default, a description with units, and what values it accepts.

    bounds limits a number, choices a string, ros_name makes a string a ROS name (a robot or
    frame name that goes into topics); constraints adds words for what none of those can say.
    A parameter is read-only unless tunable, in which case `ros2 param set` may change it while
    the node runs, under the same checks as at start.
    """

    name: str
    default: object
    description: str
    bounds: Bounds | None = None
    choices: tuple = ()
    ros_name: bool = False
    constraints: str = ''
    tunable: bool = False

    def constraint_text(self) -> str:
        words = [self.bounds.text()] if self.bounds else []
        if self.choices:
            words.append(' | '.join(self.choices))
        if self.ros_name:
            words.append('a ROS name')
        if self.constraints:
            words.append(self.constraints)
        return '; '.join(words)

    def descriptor(self) -> ParameterDescriptor:
        return ParameterDescriptor(name=self.name, type=_TYPES[type(self.default)],
                                   description=self.description,
                                   additional_constraints=self.constraint_text(),
                                   read_only=not self.tunable)

    def problem(self, value) -> str | None:
        """Return one line saying why value is not acceptable, or None."""
        if self.bounds is not None:
            return self.bounds.problem(self.name, value)
        if self.choices and value not in self.choices:
            return f'{self.name} must be one of {", ".join(self.choices)}, got {value!r}'
        if self.ros_name:
            return ros_name_problem(value, self.name)
        if isinstance(self.default, list) and not all(is_finite_number(item) for item in value):
            return f'{self.name} must hold finite numbers, got {[compact(v) for v in value]}'
        return None

    def help_line(self) -> str:
        default = self.default if self.default != '' else "''"
        constraints = self.constraint_text()
        extra = ', '.join(part for part in (constraints, 'tunable' if self.tunable else '')
                          if part)
        return f'  {self.name} [default {default}]: {self.description}' + (
            f' ({extra})' if extra else '')


def declare_parameters(node, specs):
    """Declare specs on node and return their checked values by name; problems are ConfigErrors."""
    values = {}
    for spec in specs:
        try:
            node.declare_parameter(spec.name, spec.default, spec.descriptor())
        except InvalidParameterTypeException as error:
            hint = ' (write a double with a decimal point, e.g. 50.0)' if isinstance(
                spec.default, float) else ''
            raise ConfigError(f'parameter {spec.name}: {error}{hint}') from None
        except ParameterException as error:
            raise ConfigError(f'parameter {spec.name}: {error}') from None
        value = node.get_parameter(spec.name).value
        value = list(value) if isinstance(spec.default, list) else value
        problem = spec.problem(value)
        if problem is not None:
            raise ConfigError(problem)
        values[spec.name] = value
    return values


def accept_tuning(node, specs, apply):
    """
    Let `ros2 param set` change the tunable specs while node runs.

    A request is checked whole, by the same rules as at start: if every value is acceptable,
    apply(values by name) receives them all; otherwise none is taken and the reply names the
    first problem. Read-only parameters are refused by rclpy itself.
    """
    tunable = {spec.name: spec for spec in specs if spec.tunable}

    def on_set(parameters):
        changes = {}
        for parameter in parameters:
            spec = tunable.get(parameter.name)
            if spec is None:
                continue
            problem = spec.problem(parameter.value)
            if problem is not None:
                node.get_logger().warn(f'refused: {problem}')
                return SetParametersResult(successful=False, reason=problem)
            changes[parameter.name] = parameter.value
        if changes:
            apply(changes)
            node.get_logger().info('tuned: ' + ', '.join(
                f'{name} = {compact(value)}' for name, value in changes.items()))
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(on_set)


def require(condition, message):
    """Raise ConfigError(message) unless condition holds."""
    if not condition:
        raise ConfigError(message)


def build_parser(prog, description, specs):
    """Build an argparse parser whose --help lists the node's ROS parameters."""
    epilog = '\n'.join(['ROS parameters (set with --ros-args -p name:=value; read-only unless '
                        'marked tunable, which `ros2 param set` may change while running):']
                       + [spec.help_line() for spec in specs])
    return argparse.ArgumentParser(prog=prog, description=description, epilog=epilog,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)


def run(prog, parser, make_node, argv=None):
    """
    Parse the command line, run the node until it finishes, and return an exit code.

    The node must have a `finished` future (its result is the exit code, or a ConfigError for
    input found bad while running) and a `shut_down()` method that runs before the node is
    destroyed, while it can still publish. Ctrl-C and SIGTERM end the run with exit code 0
    after shut_down(), however busy the node is.
    """
    argv = list(sys.argv if argv is None else argv)
    options = parser.parse_args(remove_ros_args(argv)[1:])
    ending = _Ending()
    # A shell starts background jobs with SIGINT ignored and ros2 launch stops nodes with SIGINT
    # then SIGTERM, so the handlers are ours whatever the parent set up.
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signal_number, ending.on_signal)
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = executor = None
    code, leave_endpoints = EXIT_OK, False
    try:
        node = make_node(options)
        node.finished.add_done_callback(lambda _: ending.complete())
        executor = EventsExecutor()
        executor.add_node(node)
        ending.node_runs = True
        while not ending.future.done():
            executor.spin_until_future_complete(ending.future, timeout_sec=SIGNAL_CHECK_PERIOD)
        code = node.finished.result() if node.finished.done() else EXIT_OK
    except ConfigError as error:
        print(f'{prog}: error: {error}', file=sys.stderr)
        code = EXIT_BAD_INPUT
    except ExternalShutdownException:
        code = EXIT_OK
    except _Interrupted:
        leave_endpoints = True
    finally:
        if executor is not None:
            executor.remove_node(node)
            executor.shutdown()
        if node is not None:
            node.shut_down()
            leave_endpoints = _endpoint_count(node) > ORDERLY_TEARDOWN_LIMIT
            if not leave_endpoints:
                node.destroy_node()
        rclpy.try_shutdown()
    if leave_endpoints:
        _exit_now(code)
    # With no node left, this deletes the DDS participant now, so peers see it go at once.
    get_default_context().destroy()
    return code


def _endpoint_count(node):
    return sum(1 for _ in node.publishers) + sum(1 for _ in node.subscriptions)


def _exit_now(code):
    """
    End the process without withdrawing the node's endpoints one by one.

    rmw republishes a node's whole list of endpoints each time one is withdrawn, so withdrawing
    thousands (a large swarm) takes tens of seconds; other nodes instead see them go when the
    middleware's lease on this process expires (about 20 s). The node has said its last words
    in shut_down() and the context is shut down: only the bookkeeping is skipped.
    """
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


class _Interrupted(Exception):
    """A signal came while the node was being built."""


class _Ending:
    """
    How a run ends: the future the executor spins on.

    While the node is being built (a large swarm takes seconds), a signal abandons the
    building. Once the node runs, Python runs signal handlers between callbacks: completing
    the future ends the spin there and then, even while timers that are always due keep the
    executor busy, where a flag would never be looked at.
    """

    def __init__(self):
        self.future = Future()
        self.node_runs = False

    def on_signal(self, *_):
        if not self.node_runs:
            raise _Interrupted()
        self.complete()

    def complete(self):
        if not self.future.done():
            self.future.set_result(None)
