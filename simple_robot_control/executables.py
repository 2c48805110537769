"""
The entry points of the package's executables, as setup.py installs them.

Each sets quiet handlers for Ctrl-C and SIGTERM before anything heavy is imported (numpy, scipy
and rclpy take about a second to load), so a signal in that second ends the program with exit
code 0 and no traceback; the node runtime takes the signals over once the node runs. The code
of each executable lives in the module named after it, listed here.
"""

from functools import partial
import importlib
import signal

MODULES = {
    'stdr_lite': 'stdr_lite.node.stdr_lite',
    'stdr_viewer': 'stdr_lite.viewer.stdr_viewer',
    'move_robot': 'stdr_lite.tools.move_robot',
    'waypoint_controller': 'waypoint_controller.waypoint_controller',
    'course_monitor': 'waypoint_controller.course_monitor',
    'plot_run': 'waypoint_controller.plot_run',
}


def _leave_quietly(signal_number, frame):
    raise SystemExit(0)


def start(name):
    """Run the executable name: signals first, then its module's main()."""
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signal_number, _leave_quietly)
    return importlib.import_module(MODULES[name]).main()


stdr_lite = partial(start, 'stdr_lite')
stdr_viewer = partial(start, 'stdr_viewer')
move_robot = partial(start, 'move_robot')
waypoint_controller = partial(start, 'waypoint_controller')
course_monitor = partial(start, 'course_monitor')
plot_run = partial(start, 'plot_run')
