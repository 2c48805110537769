"""The reference answers' nodes (see simple_robot_control/executables.py)."""

from simple_robot_control.executables import entry_points, Executable

EXECUTABLES = {
    'planner_controller': Executable(
        'coursework_answers.planner_controller',
        'coursework_answers.parameters:PLANNER_CONTROLLER_PARAMETERS'),
    'occupancy_mapper': Executable(
        'coursework_answers.occupancy_mapper',
        'coursework_answers.parameters:OCCUPANCY_MAPPER_PARAMETERS'),
}
__getattr__ = entry_points(EXECUTABLES)
