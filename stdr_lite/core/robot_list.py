"""Robot lists: the robots of a world, by name, each with its description and start pose."""

import os

from simple_robot_control.input_files import MAX_LIST_BYTES, read_yaml
from simple_robot_control.validation import compact, describe, is_finite_number, shorten
from stdr_lite.core.fields import FieldReader, RobotFileError
from stdr_lite.core.robot_description import (HEADING, load_robot, POSITION, RobotDescription,
                                              RobotEntry)


def load_robot_list(path: str | os.PathLike, default_description: RobotDescription,
                    search_path: tuple = ()) -> list[RobotEntry]:
    """
    Read a robot list: {robots: [{name, description, pose}, ...]}.

    An empty list is an empty world, where robots may be spawned later. name defaults to
    robot<K> (K its position in the list), description (a robot file in any layout, relative to
    the list's folder) to default_description, and pose [x, y, theta] to the description's
    initial_pose. search_path is where robot files' includes are looked for.
    """
    path = os.fspath(path)
    data = read_yaml(path, 'robot list', RobotFileError, MAX_LIST_BYTES)
    reader = FieldReader(path)
    data = reader.mapping(data, '')
    if 'robots' not in data:
        reader.fail('robots', 'missing (a world that starts empty says robots: [])')
    robots = reader.sequence(data, 'robots', '')
    entries = [robot_entry(item, f'robot{index}', default_description, path,
                           os.path.dirname(path), f'robots[{index}]', search_path)
               for index, item in enumerate(robots)]
    names = [entry.name for entry in entries]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        reader.fail('robots', f'names must be unique; repeated: {shorten(", ".join(duplicates))}')
    return entries


def robot_entry(item: object, default_name: str, default_description: RobotDescription,
                source: str, folder: str = '', where: str = 'robot',
                search_path: tuple = ()) -> RobotEntry:
    """Check one robot of a list and return a RobotEntry."""
    reader = FieldReader(source)
    item = reader.mapping(item if item is not None else {}, where)
    unknown = sorted(set(item) - {'name', 'description', 'pose'})
    if unknown:
        reader.fail(where, f'unknown keys {shorten(str(unknown))}; expected name, description, '
                    'pose')
    name = reader.name(item, 'name', where, default_name)
    description = default_description
    if 'description' in item:
        if not isinstance(item['description'], str):
            reader.fail(f'{where}.description', f'expected a file name, got '
                        f'{describe(item["description"])}')
        description = load_robot(os.path.join(folder, item['description']), search_path)
    pose = item.get('pose', list(description.initial_pose))
    if not isinstance(pose, list) or len(pose) != 3 or not all(map(is_finite_number, pose)):
        reader.fail(f'{where}.pose', f'expected [x, y, theta] as finite numbers, got '
                    f'{describe(pose)}')
    for axis, value, bounds in zip(('x', 'y', 'theta'), pose, (POSITION, POSITION, HEADING)):
        if not bounds.contains(value):
            reader.fail(f'{where}.pose', f'{axis} must be {bounds.text()}, got {compact(value)}')
    return RobotEntry(name, description, tuple(float(value) for value in pose))
