"""The simulator's executables (see simple_robot_control/executables.py)."""

from simple_robot_control.executables import entry_points, Executable

EXECUTABLES = {
    'stdr_lite': Executable('stdr_lite.node.stdr_lite', 'stdr_lite.node.parameters:PARAMETERS'),
    'stdr_viewer': Executable('stdr_lite.viewer.stdr_viewer',
                              'stdr_lite.viewer.parameters:PARAMETERS'),
    'move_robot': Executable('stdr_lite.tools.move_robot',
                             'stdr_lite.tools.parameters:MOVE_ROBOT_PARAMETERS'),
    'stdr_ctl': Executable('stdr_lite.tools.stdr_ctl'),
}
__getattr__ = entry_points(EXECUTABLES)
