"""
Course files: waypoint files, each with an optional YAML beside it, read and checked whole.

A course is a waypoint file of the lab's format (course.txt). A YAML file of the same name
(course.yaml) may say where the robot starts, in which world, how long the submission has,
what the course is worth, which limits are graded, and which task it asks with what
thresholds (tasks.py); anything it leaves out takes the given defaults, else the lab's own
(waypoint_lab/course.py): the bundled lab_room, the robot at the lab's start, the lab's d and
t. Angles are in degrees, as in waypoint files. grade_lab grades on them; make scenario and
scenario.launch.py bring them up. No ROS here.
"""

from dataclasses import replace
import difflib
import math
import os
from pathlib import Path

from courseworks.names import HIDES_MAP, SUBMITTED_MAP_TOPIC
from courseworks.tasks import check_task, TaskError, thresholds_for
from simple_robot_control.input_files import is_regular_file, read_yaml
from simple_robot_control.occupancy_map import load_map, MapError
from simple_robot_control.share import bundled_files
from simple_robot_control.validation import Bounds, describe, topic_name_problem
from stdr_lite.core.fields import RobotFileError
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.course import Course
from waypoint_lab.waypoints import load_waypoints, WaypointFileError

COURSE_SUFFIX = '.txt'
YAML_SUFFIXES = ('.yaml', '.yml')
MAX_COURSES = 1000
# A course on the bundled map lies within it; any map's within a thousand kilometres.
POSITION = Bounds(-1e6, 1e6)
HEADING_DEGREES = Bounds(-3600.0, 3600.0)
TIME_LIMIT_RANGE = Bounds(1.0, 86400.0)
POINTS = Bounds(0.0, 1e6)
DISTANCE_TOLERANCE_RANGE = Bounds(0.0, 10.0, low_open=True)
ANGLE_TOLERANCE_DEGREES = Bounds(0.0, 180.0, low_open=True)
GRADED_LIMIT = Bounds(0.0, 1e6, low_open=True)


class CourseError(ValueError):
    """A course that cannot be graded; the message is one line naming the file and field."""


def find_courses(paths: list[str | os.PathLike], defaults: Course | None = None) -> list[Course]:
    """
    Return the courses of paths: waypoint files, and the *.txt files of folders, by name.

    defaults gives what a course's YAML leaves out (its name and waypoints are ignored).
    Raises CourseError for a path that is neither, a folder without courses, two courses of
    one name, or a bad waypoint file or YAML.
    """
    files = []
    for path in map(Path, paths):
        if path.is_dir():
            found = sorted(child for child in path.iterdir()
                           if child.suffix == COURSE_SUFFIX and child.is_file())
            if not found:
                raise CourseError(f'{path}: a folder with no course (no *{COURSE_SUFFIX} '
                                  'waypoint file)')
            files += found
        elif path.is_file():
            files.append(path)
        else:
            raise CourseError(f'{path}: no such course file or folder')
        if len(files) > MAX_COURSES:
            raise CourseError(f'{path}: more than {MAX_COURSES} courses')
    courses = [read_course(file, defaults) for file in files]
    names = [course.name for course in courses]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise CourseError(f'two courses named {twice[0]}: rename one (course names come from '
                          'the waypoint files)')
    return courses


def read_course(path: str | os.PathLike, defaults: Course | None = None) -> Course:
    """Read one course: its waypoint file, and the YAML of the same name if there is one."""
    path = Path(path)
    try:
        waypoints = tuple(load_waypoints(path))
    except WaypointFileError as error:
        raise CourseError(str(error)) from None
    base = defaults or Course('', ())
    # Absolute, as every path a course holds: the submission runs in a folder of its own.
    course = replace(base, name=path.stem, waypoint_file=path.resolve(), waypoints=waypoints,
                     settings_file=None)
    # A course's YAML is read whatever it is: a FIFO or a folder there is refused, not skipped.
    settings = next((path.with_suffix(suffix) for suffix in YAML_SUFFIXES
                     if os.path.lexists(path.with_suffix(suffix))), None)
    return course if settings is None else _with_settings(course, settings)


def _number(source, key, value, bounds):
    problem = bounds.problem(key, value)
    if problem:
        raise CourseError(f'{source}: {problem}')
    return float(value)


def _start(source, value):
    if not (isinstance(value, list) and len(value) == 3):
        raise CourseError(f'{source}: start must be [x, y, theta] (m, m, degrees), got '
                          f'{describe(value)}')
    x, y, theta = (_number(source, f'start {name}', item, bounds) for name, item, bounds in
                   zip(('x', 'y', 'theta (degrees)'), value,
                       (POSITION, POSITION, HEADING_DEGREES)))
    return x, y, math.radians(theta)


def _world_file(source, key, value, folder):
    """
    Find a map or robot: a path is a file beside the YAML, a bare name a bundled one; checked.

    A path (anything with a suffix or a slash: `factory.yaml`, `maps/factory.yaml`) must be a
    regular file inside the course's folder (its map's image too): one that is missing, leads
    out (`..`, an absolute path, a link) or is a folder, a FIFO or a device is refused, as is a
    file the simulator would refuse, before anything runs. A bare name (`factory`) is a bundled
    world or robot, never a file of the course's: a missing file is never replaced by a bundled
    one of the same name.
    """
    if not isinstance(value, str) or not value:
        raise CourseError(f'{source}: {key} must be a file name, got {describe(value)}')
    folder = folder.resolve()
    if '/' in value or Path(value).suffix:
        path = _inside(source, key, value, folder / value, folder)
        _check_world_file(source, key, path, folder)
        return str(path)
    bundled = bundled_files('maps' if key == 'map' else 'robots')
    if value in bundled:
        return bundled[value]
    known = ', '.join(sorted(bundled)) or 'none installed'
    raise CourseError(f'{source}: {key} {value!r} is no bundled {key} ({known}); a file of '
                      f"the course's is named with its suffix ({value}.yaml)")


def _inside(source, key, value, path, folder):
    """Return path resolved, if it is a regular file inside folder; CourseError otherwise."""
    resolved = Path(path).resolve()
    if folder not in resolved.parents:
        raise CourseError(f"{source}: {key} {value!r} leads outside the course's folder "
                          f'({resolved}): a course names only files beside it, or bundled ones')
    if not os.path.lexists(resolved):
        raise CourseError(f'{source}: {key} {value!r}: no such file beside it ({resolved})')
    if not is_regular_file(resolved):
        raise CourseError(f'{source}: {key} {value!r} is no regular file (a folder, a FIFO or '
                          'a device)')
    return resolved


def _check_world_file(source, key, path, folder):
    """Load the file as the simulator will; CourseError saying why it cannot be."""
    try:
        if key == 'robot':
            load_robot(path)
            return
        description = read_yaml(path, 'map file', MapError)
        image = description.get('image') if isinstance(description, dict) else None
        if isinstance(image, str):
            _inside(path, 'image', image, Path(path).parent / image, folder)
        load_map(path)
    except (MapError, RobotFileError) as error:
        raise CourseError(f'{source}: {key}: {error}') from None


def _with_settings(course, path):
    """Apply a course's YAML to it; CourseError names the file and the field at fault."""
    settings = read_yaml(path, 'course settings', CourseError)
    source = str(path)
    if settings is None:
        return replace(course, settings_file=path)
    if not isinstance(settings, dict):
        raise CourseError(f'{source}: course settings must be a mapping of fields, got '
                          f'{describe(settings)}')
    changes = {'settings_file': path}
    for key, value in settings.items():
        if key not in _FIELDS:
            close = difflib.get_close_matches(str(key), _FIELDS, n=1)
            hint = f'; did you mean {close[0]}?' if close else f' (known: {", ".join(_FIELDS)})'
            raise CourseError(f'{source}: unknown field {describe(key)}{hint}')
        changes.update(_FIELDS[key](source, value, path.parent))
    try:
        # A course's thresholds are its task's: read once the task is known.
        changes['thresholds'] = thresholds_for(changes.get('task', course.task),
                                               settings.get('thresholds'))
    except TaskError as error:
        raise CourseError(f'{source}: {error}') from None
    return replace(course, **changes)


def _map_topic(source, value):
    problem = topic_name_problem(value, 'map_topic')
    if problem:
        raise CourseError(f'{source}: {problem}')
    return {'map_topic': value if value.startswith('/') else f'/{value}'}


def submitted_map_topic(course: Course) -> str:
    """Return where a mapping course's submission publishes its map (its YAML's map_topic)."""
    return course.map_topic or SUBMITTED_MAP_TOPIC


def _task(source, value):
    try:
        return {'task': check_task(value)}
    except TaskError as error:
        raise CourseError(f'{source}: {error}') from None


_FIELDS = {
    'start': lambda source, value, _: {'start': _start(source, value)},
    'map': lambda source, value, folder: {'map_file': _world_file(source, 'map', value,
                                                                  folder)},
    'robot': lambda source, value, folder: {'robot_file': _world_file(source, 'robot', value,
                                                                      folder)},
    'time_limit': lambda source, value, _: {'time_limit': _number(source, 'time_limit', value,
                                                                  TIME_LIMIT_RANGE)},
    'points': lambda source, value, _: {'points': _number(source, 'points', value, POINTS)},
    'distance_tolerance': lambda source, value, _: {'distance_tolerance': _number(
        source, 'distance_tolerance', value, DISTANCE_TOLERANCE_RANGE)},
    'angle_tolerance_deg': lambda source, value, _: {'angle_tolerance': math.radians(_number(
        source, 'angle_tolerance_deg', value, ANGLE_TOLERANCE_DEGREES))},
    'max_time': lambda source, value, _: {'max_time': _number(source, 'max_time', value,
                                                              GRADED_LIMIT)},
    'max_path_length': lambda source, value, _: {'max_path_length': _number(
        source, 'max_path_length', value, GRADED_LIMIT)},
    'task': lambda source, value, _: _task(source, value),
    'thresholds': lambda source, value, _: {},
    'map_topic': lambda source, value, _: _map_topic(source, value),
}


def world_parameters(course: Course) -> dict:
    """
    Return stdr_lite's parameters for course's world: its start, map and robot, if given.

    A task whose robot builds its own map has the world's map hidden (its geometry alone).
    """
    parameters = {'initial_pose': [float(value) for value in course.start],
                  'map_visible': course.task not in HIDES_MAP}
    if course.map_file:
        parameters['map_yaml'] = str(course.map_file)
    if course.robot_file:
        parameters['robot_description'] = str(course.robot_file)
    return parameters


def course_files(courses: list[Course]) -> list[Path]:
    """Return every file the courses are read from: waypoints, YAML, maps and their images."""
    files = []
    for course in courses:
        files.append(Path(course.waypoint_file))
        files += [Path(course.waypoint_file).with_suffix(suffix) for suffix in YAML_SUFFIXES]
        for extra in (course.map_file, course.robot_file):
            if extra:
                files.append(Path(extra))
        if course.map_file:
            try:
                image = read_yaml(course.map_file, 'map', CourseError).get('image')
            except (CourseError, AttributeError):
                image = None
            if isinstance(image, str):
                files.append(Path(course.map_file).parent / image)
    return [file for file in files if file.is_file()]
