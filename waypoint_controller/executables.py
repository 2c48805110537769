"""The lab's answer as an executable (see simple_robot_control/executables.py)."""

from simple_robot_control.executables import entry_points, Executable

EXECUTABLES = {
    'waypoint_controller': Executable('waypoint_controller.waypoint_controller',
                                      'waypoint_controller.parameters:PARAMETERS'),
}
__getattr__ = entry_points(EXECUTABLES)
