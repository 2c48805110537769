"""
Robot descriptions in STDR's robot YAML format: footprint, initial pose, lasers and sonars.

The format is the one STDR's GUI saves and its bundled robots use (pandora_robot.yaml,
khepera2.yaml): top-level initial_pose {x, y, theta}, footprint {radius, points},
kinematic, and sensors {lasers: [...], sonars: [...], rfids: [...]}. A laser has min_angle,
max_angle, min_range, max_range, num_rays, frequency, frame_id, pose {x, y, theta} and noise
{mean, std}; a sonar has cone_angle instead of the angles and rays. Lengths are metres,
angles radians, frequencies hertz.
"""

from dataclasses import dataclass
import os

from simple_robot_control.validation import is_finite_number, is_ros_name, ROS_NAME_RULE
from simple_robot_control.yaml_file import read_yaml


class RobotFileError(ValueError):
    """A robot description that cannot be used; the message is one line naming file and key."""


@dataclass(frozen=True)
class Noise:
    """Gaussian noise added to every range reading, as the description specifies it."""

    mean: float = 0.0
    std: float = 0.0


@dataclass(frozen=True)
class LaserSpec:
    frame_id: str
    pose: tuple
    min_angle: float
    max_angle: float
    min_range: float
    max_range: float
    num_rays: int
    frequency: float
    noise: Noise


@dataclass(frozen=True)
class SonarSpec:
    frame_id: str
    pose: tuple
    cone_angle: float
    min_range: float
    max_range: float
    frequency: float
    noise: Noise


@dataclass(frozen=True)
class RobotDescription:
    radius: float
    initial_pose: tuple
    lasers: tuple = ()
    sonars: tuple = ()


def load_robot(path: str | os.PathLike) -> 'RobotDescription':
    """Read and check an STDR robot YAML file."""
    path = os.fspath(path)
    return parse_robot(read_yaml(path, 'robot file', RobotFileError), path)


def parse_robot(data: object, source: str = '<robot>') -> 'RobotDescription':
    """Check a robot description already read from YAML; return a RobotDescription."""
    reader = _Reader(source)
    if isinstance(data, dict) and 'robot' in data:
        reader.fail('robot', "STDR's nested robot_specifications format is not supported; "
                    'use the flat format (initial_pose, footprint, sensors)')
    data = reader.mapping(data, '')
    footprint = reader.mapping(data.get('footprint', {}), 'footprint')
    if footprint.get('points'):
        reader.fail('footprint.points', 'polygon footprints are not supported; give a radius')
    radius = reader.number(footprint, 'radius', 'footprint', positive=True)
    sensors = reader.mapping(data.get('sensors', {}) or {}, 'sensors')
    lasers = tuple(_laser(reader, item, f'sensors.lasers[{index}]')
                   for index, item in enumerate(reader.sequence(sensors, 'lasers', 'sensors')))
    sonars = tuple(_sonar(reader, item, f'sensors.sonars[{index}]')
                   for index, item in enumerate(reader.sequence(sensors, 'sonars', 'sensors')))
    return RobotDescription(radius, reader.pose(data, 'initial_pose', ''), lasers, sonars)


def _laser(reader, item, where):
    item = reader.mapping(item, where)
    spec = LaserSpec(
        frame_id=reader.name(item, 'frame_id', where),
        pose=reader.pose(item, 'pose', where),
        min_angle=reader.number(item, 'min_angle', where),
        max_angle=reader.number(item, 'max_angle', where),
        min_range=reader.number(item, 'min_range', where, non_negative=True),
        max_range=reader.number(item, 'max_range', where, positive=True),
        num_rays=reader.count(item, 'num_rays', where),
        frequency=reader.number(item, 'frequency', where, positive=True),
        noise=reader.noise(item, where))
    if spec.max_angle < spec.min_angle:
        reader.fail(f'{where}.max_angle', f'{spec.max_angle} is below min_angle {spec.min_angle}')
    reader.check_ranges(spec, where)
    return spec


def _sonar(reader, item, where):
    item = reader.mapping(item, where)
    spec = SonarSpec(
        frame_id=reader.name(item, 'frame_id', where),
        pose=reader.pose(item, 'pose', where),
        cone_angle=reader.number(item, 'cone_angle', where, positive=True),
        min_range=reader.number(item, 'min_range', where, non_negative=True),
        max_range=reader.number(item, 'max_range', where, positive=True),
        frequency=reader.number(item, 'frequency', where, positive=True),
        noise=reader.noise(item, where))
    reader.check_ranges(spec, where)
    return spec


class _Reader:
    """Typed access to YAML values; every complaint names the file and the key."""

    def __init__(self, source):
        self.source = source

    def fail(self, key, problem):
        raise RobotFileError(f'{self.source}: {key}: {problem}')

    def mapping(self, value, key):
        if not isinstance(value, dict):
            self.fail(key or 'top level', f'expected a mapping, got {value!r}')
        return value

    def sequence(self, data, key, where):
        value = data.get(key) or []
        if not isinstance(value, list):
            self.fail(f'{where}.{key}', f'expected a list, got {value!r}')
        return value

    def number(self, data, key, where, positive=False, non_negative=False):
        name = f'{where}.{key}' if where else key
        if key not in data:
            self.fail(name, 'missing')
        value = data[key]
        if not is_finite_number(value):
            self.fail(name, f'expected a finite number, got {value!r}')
        if positive and value <= 0:
            self.fail(name, f'must be positive, got {value}')
        if non_negative and value < 0:
            self.fail(name, f'must not be negative, got {value}')
        return float(value)

    def count(self, data, key, where):
        value = self.number(data, key, where, positive=True)
        if value != int(value):
            self.fail(f'{where}.{key}', f'expected a whole number, got {data[key]!r}')
        return int(value)

    def name(self, data, key, where, default=None):
        value = data.get(key, default)
        if not is_ros_name(value):
            self.fail(f'{where}.{key}', f'expected {ROS_NAME_RULE}, got {value!r}')
        return value

    def pose(self, data, key, where):
        name = f'{where}.{key}' if where else key
        pose = self.mapping(data.get(key, {'x': 0, 'y': 0, 'theta': 0}), name)
        return tuple(self.number(pose, axis, name) for axis in ('x', 'y', 'theta'))

    def noise(self, data, where):
        noise = self.mapping(data.get('noise') or {'mean': 0, 'std': 0}, f'{where}.noise')
        return Noise(self.number(noise, 'mean', f'{where}.noise'),
                     self.number(noise, 'std', f'{where}.noise', non_negative=True))

    def check_ranges(self, spec, where):
        if spec.max_range <= spec.min_range:
            self.fail(f'{where}.max_range',
                      f'{spec.max_range} must exceed min_range {spec.min_range}')


@dataclass(frozen=True)
class RobotEntry:
    """One robot of a world: its name, its description, and where it starts."""

    name: str
    description: RobotDescription
    pose: tuple


def load_robot_list(path: str | os.PathLike,
                    default_description: RobotDescription) -> list[RobotEntry]:
    """
    Read a robot list: {robots: [{name, description, pose}, ...]}.

    name defaults to robot<K> (K its position in the list), description (an STDR robot file,
    relative to the list's folder) to default_description, and pose [x, y, theta] to the
    description's initial_pose.
    """
    path = os.fspath(path)
    data = read_yaml(path, 'robot list', RobotFileError)
    reader = _Reader(path)
    robots = reader.sequence(reader.mapping(data, ''), 'robots', '')
    if not robots:
        reader.fail('robots', 'the list is empty')
    entries = [robot_entry(item, f'robot{index}', default_description, path,
                           os.path.dirname(path), f'robots[{index}]')
               for index, item in enumerate(robots)]
    names = [entry.name for entry in entries]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        reader.fail('robots', f'names must be unique; repeated: {", ".join(duplicates)}')
    return entries


def robot_entry(item: object, default_name: str, default_description: RobotDescription,
                source: str, folder: str = '', where: str = 'robot') -> RobotEntry:
    """Check one robot of a list (or of an add_robot request) and return a RobotEntry."""
    reader = _Reader(source)
    item = reader.mapping(item if item is not None else {}, where)
    unknown = sorted(set(item) - {'name', 'description', 'pose'})
    if unknown:
        reader.fail(where, f'unknown keys {unknown}; expected name, description, pose')
    name = reader.name(item, 'name', where, default_name)
    description = default_description
    if 'description' in item:
        if not isinstance(item['description'], str):
            reader.fail(f'{where}.description', f'expected a file name, got '
                        f'{item["description"]!r}')
        description = load_robot(os.path.join(folder, item['description']))
    pose = item.get('pose', list(description.initial_pose))
    if not isinstance(pose, list) or len(pose) != 3 or not all(map(is_finite_number, pose)):
        reader.fail(f'{where}.pose', f'expected [x, y, theta] as finite numbers, got {pose!r}')
    return RobotEntry(name, description, tuple(float(value) for value in pose))
