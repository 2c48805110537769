"""The live view's executable (see simple_robot_control/executables.py)."""

from simple_robot_control.executables import entry_points, Executable

EXECUTABLES = {
    'foxglove_live': Executable('foxglove_live.foxglove_live',
                                'foxglove_live.parameters:PARAMETERS'),
}
__getattr__ = entry_points(EXECUTABLES)
