"""
The entry points of the package's executables, as setup.py installs them.

Each sets quiet handlers for Ctrl-C and SIGTERM before anything heavy is imported (numpy, scipy
and rclpy take about a second to load), then takes the signals held since the interpreter's
first lines (early_signals.py), so a signal in that second ends the program with exit code 0
and no traceback; the node runtime takes the signals over once the node runs. Then the ROS
parameters of the command line are judged against the node's table (a light module), so a
bad value is refused in a tenth of a second, before that load. The code of each executable
lives in the module named after it, listed here with its parameter table.
"""

from functools import partial
import importlib
import os
import signal
import sys

from simple_robot_control.early_parameters import early_problem
from simple_robot_control.early_signals import release_signals
from simple_robot_control.exit_codes import EXIT_BAD_INPUT

# The one list of the executables: each one's module (setup.py installs a console script for
# each name, whose entry point is this module's attribute of that name), and its node's parameter
# table ('module:NAME') where it takes ROS parameters. A literal, which setup.py reads as text.
MODULES = {
    'stdr_lite': 'stdr_lite.node.stdr_lite',
    'stdr_viewer': 'stdr_lite.viewer.stdr_viewer',
    'move_robot': 'stdr_lite.tools.move_robot',
    'stdr_ctl': 'stdr_lite.tools.stdr_ctl',
    'waypoint_controller': 'waypoint_controller.waypoint_controller',
    'course_monitor': 'waypoint_lab.course_monitor',
    'plot_run': 'waypoint_lab.plot_run',
    'record_run': 'waypoint_lab.record_run',
    'foxglove_live': 'foxglove_live.foxglove_live',
    'grade_lab': 'lab_grader.grade_lab',
    'policy_controller': 'waypoint_lab.learning.policy_controller',
    'planner_controller': 'coursework_answers.planner_controller',
    'occupancy_mapper': 'coursework_answers.occupancy_mapper',
}
PARAMETER_TABLES = {
    'stdr_lite': 'stdr_lite.node.parameters:PARAMETERS',
    'stdr_viewer': 'stdr_lite.viewer.parameters:PARAMETERS',
    'move_robot': 'stdr_lite.tools.parameters:MOVE_ROBOT_PARAMETERS',
    'waypoint_controller': 'waypoint_controller.parameters:PARAMETERS',
    'course_monitor': 'waypoint_lab.parameters:COURSE_MONITOR_PARAMETERS',
    'record_run': 'waypoint_lab.parameters:RECORD_RUN_PARAMETERS',
    'foxglove_live': 'foxglove_live.parameters:PARAMETERS',
    'policy_controller': 'waypoint_lab.parameters:POLICY_CONTROLLER_PARAMETERS',
    'planner_controller': 'coursework_answers.parameters:PLANNER_CONTROLLER_PARAMETERS',
    'occupancy_mapper': 'coursework_answers.parameters:OCCUPANCY_MAPPER_PARAMETERS',
}


def _end_at_once(signal_number, frame):
    os._exit(0)


def _leave_quietly(signal_number, frame):
    raise SystemExit(0)


def parameter_table(name: str) -> tuple:
    """Return the ParameterSpecs of the executable name's node; () where it takes none."""
    if name not in PARAMETER_TABLES:
        return ()
    module, _, table = PARAMETER_TABLES[name].partition(':')
    return getattr(importlib.import_module(module), table)


def _refuse_early(name):
    """End the program with the node's own refusal of a parameter, where sure of it."""
    specs = parameter_table(name)
    problem = early_problem(sys.argv, name, specs) if specs else None
    if problem is not None:
        print(f'{name}: error: {problem}', file=sys.stderr)
        sys.stderr.flush()
        os._exit(EXIT_BAD_INPUT)


def _handle_signals(handler):
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signal_number, handler)


def start(name):
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
    _refuse_early(name)
    module = importlib.import_module(MODULES[name])
    _handle_signals(_leave_quietly)
    try:
        code = module.main()
    except SystemExit as ending:
        code = ending.code
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code if isinstance(code, int) else (0 if code is None else 1))


def __getattr__(name: str):
    """Return the entry point of the executable name, as a console script imports it."""
    if name not in MODULES:
        raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
    return partial(start, name)
