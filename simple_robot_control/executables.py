"""
How the package's executables start, for each package that declares some.

Each package declares its executables in its own executables.py: a table of Executable (the
module that holds its main(), within that package, and its node's parameter table), and the
entry points, entry_points(table), as its module __getattr__. setup.py installs a console script
for each, whose entry point is `<package>.executables:<name>`. Each sets quiet handlers for
Ctrl-C and SIGTERM before anything heavy is imported (numpy, scipy and rclpy take about a second
to load), then takes the signals held since the interpreter's first lines (early_signals.py),
so a signal in that second ends the program with exit code 0 and no traceback; the node runtime
takes the signals over once the node runs. Then the ROS parameters of the command line are
judged against the node's table (a light module), so a bad value is refused in a tenth of a
second, before that load. An executable that needs ROS 2 says so in one line where this Python
lacks it (the Python API, the environments, the judges and plot_run need none).
"""

from dataclasses import dataclass
from functools import partial
import importlib
import importlib.util
import os
import re
import signal
import sys
from typing import Callable

from simple_robot_control.early_parameters import early_problem
from simple_robot_control.early_signals import release_signals
from simple_robot_control.exit_codes import EXIT_BAD_INPUT, EXIT_FAILED

# ROS 2's Python modules (rclpy, rcl's, the interface packages), and where ROS 2 comes from,
# said to whoever runs a ROS executable in a Python without them.
ROS_MODULE = re.compile(r'^(rclpy|rcl_\w+|rosidl\w*|rpyutils|\w+_msgs|\w+_interfaces)(\.|$)')
ROS_SOURCES = ('`make install` gives .venv the ROS 2 Jazzy wheels (Linux x86_64), a sourced Jazzy '
               'install has it; elsewhere, the container (doc/install.md)')


@dataclass(frozen=True)
class Executable:
    """
    An executable: the module of its main(), its node's parameter table ('module:NAME').

    ros says whether it needs ROS 2 (rclpy) to run.
    """

    module: str
    parameters: str = ''
    ros: bool = True

    def parameter_table(self) -> tuple:
        """Return the ParameterSpecs of its node; () where it takes none."""
        if not self.parameters:
            return ()
        module, _, table = self.parameters.partition(':')
        return getattr(importlib.import_module(module), table)


def _end_at_once(signal_number, frame):
    os._exit(0)


def _leave_quietly(signal_number, frame):
    raise SystemExit(0)


def _refuse_early(name, executable):
    """End the program with the node's own refusal of a parameter, where sure of it."""
    specs = executable.parameter_table()
    problem = early_problem(sys.argv, name, specs) if specs else None
    if problem is not None:
        print(f'{name}: error: {problem}', file=sys.stderr)
        sys.stderr.flush()
        os._exit(EXIT_BAD_INPUT)


def _load(name, executable):
    """Import the executable's module; where it needs ROS 2 and this Python lacks it, one line."""
    try:
        # Found, not loaded: a refused command line does not wait for rclpy.
        if executable.ros and importlib.util.find_spec('rclpy') is None:
            raise ModuleNotFoundError("No module named 'rclpy'", name='rclpy')
        return importlib.import_module(executable.module)
    except ModuleNotFoundError as error:
        if not executable.ros or not ROS_MODULE.match(error.name or ''):
            raise
        print(f'{name}: error: needs ROS 2, and this Python has no module {error.name!r}: '
              f'{ROS_SOURCES}', file=sys.stderr)
        sys.stderr.flush()
        os._exit(EXIT_FAILED)


def _handle_signals(handler):
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signal_number, handler)


def start(name: str, executable: Executable) -> None:
    """
    Run the executable name: signals first, then its module's main(), then exit at once.

    While modules load, a signal ends the process on the spot: an exception raised inside a
    compiled extension's initialisation (matplotlib's, numpy's) comes out as an ImportError
    with a traceback, and nothing has been opened yet that needs closing.

    When main() is over, the node is destroyed, its context shut down, its files closed and its
    last words said: the interpreter's own teardown of numpy, scipy, pygame and rclpy objects
    would add a third of a second or more on a loaded machine, so the process ends there.
    """
    _handle_signals(_end_at_once)
    release_signals()
    _refuse_early(name, executable)
    module = _load(name, executable)
    _handle_signals(_leave_quietly)
    try:
        code = module.main()
    except SystemExit as ending:
        code = ending.code
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code if isinstance(code, int) else (0 if code is None else 1))


def entry_points(executables: dict[str, Executable]) -> Callable[[str], Callable[[], None]]:
    """Return a package's module __getattr__: each executable's entry point, by its name."""
    def entry_point(name: str) -> Callable[[], None]:
        if name not in executables:
            raise AttributeError(f'no executable {name!r}')
        return partial(start, name, executables[name])
    return entry_point
