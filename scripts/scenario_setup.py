"""
Print what bringing a scenario up takes, and write stdr_lite's parameters for its world.

The lines printed: its goal file, its task's reference controller, its map, its robot's
radius, the controller's parameters (name:=value words), the nodes run beside it (a mapper),
the topic of the map a mapping task judges (empty for other tasks); the parameters file holds
the world's start, map and robot.

    python3 scripts/scenario_setup.py SCENARIO PARAMETERS_FILE

SCENARIO is a bundled scenario's name (factory_planning) or a course file's path. One line on
stderr and exit code 2 for a scenario that is not one, or a task with no bundled answer.
"""

from pathlib import Path
import sys

from coursework_answers.answers import REFERENCE_ANSWERS
from courseworks.courses import CourseError, read_course, submitted_map_topic, world_parameters
from courseworks.names import MAPPING
from simple_robot_control.share import shared_file
from stdr_lite.core.loading import map_file, robot_file
from stdr_lite.core.robot_description import load_robot
import yaml


def main(argv: list[str]) -> int:
    name, parameters_file = argv[1:3]
    try:
        path = scenario_file(name)
        course = read_course(path)
    except CourseError as error:
        print(f'scenario: {error}', file=sys.stderr)
        return 2
    if course.task not in REFERENCE_ANSWERS:
        print(f'scenario: {path}: the {course.task} task has no bundled answer yet',
              file=sys.stderr)
        return 2
    Path(parameters_file).write_text(yaml.safe_dump(
        {'stdr_lite': {'ros__parameters': world_parameters(course)}}))
    answer = REFERENCE_ANSWERS[course.task]
    print(course.waypoint_file)
    print(answer.controller)
    print(map_file(course.map_file))
    print(load_robot(robot_file(course.robot_file)).radius)
    print(' '.join(f'{name}:={value}' for name, value in answer.parameters.items()))
    print(' '.join(answer.helpers))
    print(submitted_map_topic(course) if course.task == MAPPING else '')
    return 0


def scenario_file(name: str) -> Path:
    """Return the course file a scenario's name means; CourseError if none."""
    path = Path(name) if name.endswith('.txt') else Path(shared_file('scenarios', f'{name}.txt'))
    if not path.is_file():
        known = sorted(child.stem for child in Path(shared_file('scenarios')).glob('*.txt'))
        raise CourseError(f'{name!r} is neither a course file nor a bundled scenario '
                          f'({", ".join(known)})')
    return path


if __name__ == '__main__':
    sys.exit(main(sys.argv))
