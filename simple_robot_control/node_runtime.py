"""What every executable of this package shares: the command line, main(), and its ending."""

import argparse
from collections.abc import Callable, Sequence
import os
import re
import select
import signal
import sys
import threading
import time

import rclpy
from rclpy.exceptions import NameValidationException
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future
from rclpy.utilities import get_default_context, remove_ros_args
from simple_robot_control.command_line import OneLineParser
from simple_robot_control.exit_codes import EXIT_BAD_INPUT, EXIT_OK
from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import ConfigError

SIGNAL_CHECK_PERIOD = 0.1
# Up to this many publishers and subscriptions, a node is taken down endpoint by endpoint. The
# teardown grows with the square of the count: 807 endpoints took 0.37 s here, over 1 s on a
# loaded machine; 400 take about 0.1 s.
ORDERLY_TEARDOWN_LIMIT = 400
# After Ctrl-C or SIGTERM a program has this long to say its last words, plus what its node
# asks for to finish what it writes (a bag: see ending_allowance); then it ends anyway. Ending
# the process may take 0.2 s more on a loaded machine (1.12 s measured with 0.9 here, two busy
# loops beside the tests): the promise is an end within 1 s, or that allowance more.
LAST_WORDS = 0.6
# A second Ctrl-C or SIGTERM ends the process at once with this code (128 + SIGINT, as a shell
# reports a program interrupted): what it was writing is left as it is.
EXIT_INTERRUPTED_TWICE = 130
ENDING_SIGNALS = (signal.SIGINT, signal.SIGTERM)
# rcl reports where in its C sources it found a problem: of no use to the user.
_SOURCE_LOCATION = re.compile(r'(?:, at [^,]*\.c:\d+)+')


def build_parser(prog: str, description: str, specs: Sequence[ParameterSpec]
                 ) -> argparse.ArgumentParser:
    """Build an argparse parser whose --help lists the node's ROS parameters."""
    epilog = '\n'.join(['ROS parameters (set with --ros-args -p name:=value; read-only unless '
                        'marked tunable, which `ros2 param set` may change while running):']
                       + [spec.help_line() for spec in specs])
    return OneLineParser(prog=prog, description=description, epilog=epilog,
                         formatter_class=argparse.RawDescriptionHelpFormatter)


def run(prog: str, parser: argparse.ArgumentParser, make_node: Callable,
        argv: list[str] | None = None) -> int:
    """
    Parse the command line, run the node until it finishes, and return an exit code.

    The node must have a `finished` future (its result is the exit code, or a ConfigError for
    input found bad while running) and a `shut_down()` method that runs before the node is
    destroyed, while it can still publish. Ctrl-C and SIGTERM end the run with exit code 0
    after shut_down(), however busy the node is: within LAST_WORDS, plus the seconds its
    `ending_allowance()` returns if it has one (a recorder finishing its bag). A second signal
    ends it at once.
    """
    argv = list(sys.argv if argv is None else argv)
    try:
        options = parser.parse_args(remove_ros_args(argv)[1:])
    except rclpy_implementation.RCLInvalidROSArgsError as error:
        print(f'{prog}: error: bad --ros-args: {rcl_problem(error)}', file=sys.stderr)
        return EXIT_BAD_INPUT
    running = _Running()
    code, leave_endpoints = EXIT_OK, False
    try:
        running.start(argv, lambda: make_node(options))
        code = running.spin()
    except ConfigError as error:
        print(f'{prog}: error: {error}', file=sys.stderr)
        code = EXIT_BAD_INPUT
    except ExternalShutdownException:
        code = EXIT_OK
    except _Interrupted:
        # Stopped while starting: rclpy may be half way through its own start, so nothing of
        # it is touched again; the process just ends.
        _exit_now(EXIT_OK)
    finally:
        leave_endpoints = running.tear_down()
    if leave_endpoints:
        _exit_now(code)
    # With no node left, this deletes the DDS participant now, so peers see it go at once.
    get_default_context().destroy()
    return code


class _Running:
    """The node and its executor, as far as they were made: started, spun, taken down."""

    def __init__(self):
        self.ending = _Ending()
        self.node = self.executor = None

    def start(self, argv, make_node):
        """Take the ending signals, start ROS, make the node (ConfigError if it cannot)."""
        # A shell starts background jobs with SIGINT ignored and ros2 launch stops nodes with
        # SIGINT then SIGTERM, so the handlers are ours whatever the parent set up. A signal
        # from here on abandons the start (_Interrupted), even while the watch is being set up.
        ending = self.ending
        for signal_number in ENDING_SIGNALS:
            signal.signal(signal_number, ending.on_signal)
        watch = _watch_for_signals()
        try:
            rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
        except rclpy_implementation.RCLError as error:
            raise ConfigError(f'cannot start ROS: {rcl_problem(error)}') from None
        try:
            self.node = node = make_node()
        except NameValidationException as error:
            raise ConfigError(f'{error} (check the --ros-args remappings)') from None
        node.finished.add_done_callback(lambda _: ending.complete())
        watch.allowance = getattr(node, 'ending_allowance', None)
        self.executor = EventsExecutor()
        self.executor.add_node(node)
        ending.node_runs = True

    def spin(self):
        """Run the node until it finishes or a signal ends it; return the exit code."""
        while not self.ending.future.done():
            self.executor.spin_until_future_complete(self.ending.future,
                                                     timeout_sec=SIGNAL_CHECK_PERIOD)
        finished = self.node.finished
        return finished.result() if finished.done() else EXIT_OK

    def tear_down(self):
        """Shut the node down; return whether its endpoints are left for the process's end."""
        node, executor = self.node, self.executor
        leave_endpoints = False
        if executor is not None:
            executor.remove_node(node)
            executor.shutdown()
        if node is not None:
            node.shut_down()
            leave_endpoints = _endpoint_count(node) > ORDERLY_TEARDOWN_LIMIT
            if not leave_endpoints:
                node.destroy_node()
        rclpy.try_shutdown()
        return leave_endpoints


def rcl_problem(error: Exception) -> str:
    """Say in one line what rcl found wrong, without the places in its C sources."""
    text = ' '.join(_SOURCE_LOCATION.sub('', str(error)).split())
    return text.removeprefix('Failed to parse ROS arguments: ')


def _watch_for_signals():
    """
    End the process in time after Ctrl-C or SIGTERM, whatever its main thread is doing.

    Python runs a signal handler only between bytecodes of the main thread, so a long call
    into compiled code would hold it back. The signal's arrival is also written to a pipe, at
    once, by the interpreter's own low-level handler; a thread waiting on the pipe ends the
    process if the orderly ending has not done so in time: LAST_WORDS, plus what the node's
    allowance (set on the returned watch once the node exists) asks for at that moment. A
    second signal ends it at once.
    """
    read_end, write_end = os.pipe()
    os.set_blocking(write_end, False)
    signal.set_wakeup_fd(write_end, warn_on_full_buffer=False)
    watch = _SignalWatch()

    def ending_signal(timeout=None):
        """Wait for SIGINT or SIGTERM (the pipe holds each signal's number); say if it came."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while deadline is None or (left := deadline - time.monotonic()) > 0:
            if deadline is None or select.select([read_end], [], [], left)[0]:
                if os.read(read_end, 1)[0] in ENDING_SIGNALS:
                    return True
        return False

    def wait():
        ending_signal()
        code = EXIT_INTERRUPTED_TWICE if ending_signal(
            LAST_WORDS + watch.seconds_asked()) else EXIT_OK
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    threading.Thread(target=wait, name='signal watch', daemon=True).start()
    return watch


class _SignalWatch:
    """What the signal watch asks of the node: allowance() gives seconds more to end in."""

    def __init__(self):
        self.allowance = None

    def seconds_asked(self):
        try:
            return max(0.0, float(self.allowance())) if self.allowance is not None else 0.0
        except Exception:  # noqa: B902  whatever the node's estimate raises, the end comes
            return 0.0


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


class _Interrupted(BaseException):
    """A signal came while ROS or the node was starting."""


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
