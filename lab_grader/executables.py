"""The grader's executable (see simple_robot_control/executables.py)."""

from simple_robot_control.executables import entry_points, Executable

EXECUTABLES = {
    'grade_lab': Executable('lab_grader.grade_lab'),
}
__getattr__ = entry_points(EXECUTABLES)
