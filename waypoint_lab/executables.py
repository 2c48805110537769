"""The lab's tools and the learned policy's node (see simple_robot_control/executables.py)."""

from simple_robot_control.executables import entry_points, Executable

EXECUTABLES = {
    'course_monitor': Executable('waypoint_lab.course_monitor',
                                 'waypoint_lab.parameters:COURSE_MONITOR_PARAMETERS'),
    'plot_run': Executable('waypoint_lab.plot_run', ros=False),
    'record_run': Executable('waypoint_lab.record_run',
                             'waypoint_lab.parameters:RECORD_RUN_PARAMETERS'),
    'policy_controller': Executable('waypoint_lab.learning.policy_controller',
                                    'waypoint_lab.parameters:POLICY_CONTROLLER_PARAMETERS'),
}
__getattr__ = entry_points(EXECUTABLES)
