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
import math
import os

from simple_robot_control.input_files import MAX_LIST_BYTES, read_yaml
from simple_robot_control.validation import (Bounds, compact, describe, FINITE, is_finite_number,
                                             is_ros_name, ROS_NAME_RULE, shorten)


# What a description may hold: generous for any small robot, finite everywhere, so a typo such
# as a frequency of 1e12 is refused where it is read rather than failing in a later step.
MAX_RADIUS = 5.0
RADIUS = Bounds(0.0, MAX_RADIUS, low_open=True)
MOUNT_OFFSET = Bounds(-10.0, 10.0)
HEADING = Bounds(-2.0 * math.pi, 2.0 * math.pi)
POSITION = Bounds(-1e6, 1e6)
LASER_ANGLE = Bounds(-math.pi, math.pi)
CONE_ANGLE = Bounds(0.0, math.pi, low_open=True)
MIN_RANGE = Bounds(0.0, 1000.0)
MAX_RANGE = Bounds(0.0, 1000.0, low_open=True)
RAYS = Bounds(1, 10000)
FREQUENCY = Bounds(0.001, 1000.0)
NOISE_MEAN = Bounds(-1.0, 1.0)
NOISE_STD = Bounds(0.0, 1.0)
# Each sensor is a topic of its own, and endpoints are what a swarm costs most: twice the
# sensors of STDR's most equipped robot (khepera3, 14).
MAX_SENSORS = 32
# A robot's own topics, /<robot>/<name>: a sensor's topic is /<robot>/<frame_id>, so no sensor
# may take one of these names.
ROBOT_TOPICS = ('cmd_vel', 'odom', 'ground_truth', 'initialpose')


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
    radius = reader.number(footprint, 'radius', 'footprint', RADIUS)
    sensors = reader.mapping(data.get('sensors', {}) or {}, 'sensors')
    laser_items = reader.sequence(sensors, 'lasers', 'sensors')
    sonar_items = reader.sequence(sensors, 'sonars', 'sensors')
    if len(laser_items) + len(sonar_items) > MAX_SENSORS:
        reader.fail('sensors', f'{len(laser_items) + len(sonar_items)} sensors; a robot carries '
                    f'at most {MAX_SENSORS} (STDR robots carry up to 14)')
    lasers = tuple(_laser(reader, item, f'sensors.lasers[{index}]')
                   for index, item in enumerate(laser_items))
    sonars = tuple(_sonar(reader, item, f'sensors.sonars[{index}]')
                   for index, item in enumerate(sonar_items))
    _check_sensor_names(reader, lasers, sonars)
    return RobotDescription(radius, reader.pose(data, 'initial_pose', '', POSITION), lasers,
                            sonars)


def _check_sensor_names(reader, lasers, sonars):
    """Each sensor's frame_id names its topic: none may be the robot's own, none repeated."""
    seen = {}
    for kind, specs in (('lasers', lasers), ('sonars', sonars)):
        for index, spec in enumerate(specs):
            where = f'sensors.{kind}[{index}].frame_id'
            if spec.frame_id in ROBOT_TOPICS:
                reader.fail(where, f'{spec.frame_id!r} names one of the robot topics '
                            f'({", ".join(ROBOT_TOPICS)}); name the sensor otherwise')
            if spec.frame_id in seen:
                reader.fail(where, f'{spec.frame_id!r} is the frame_id of {seen[spec.frame_id]} '
                            'too: each sensor needs its own (it names its topic and frame)')
            seen[spec.frame_id] = where.removesuffix('.frame_id')


def _laser(reader, item, where):
    item = reader.mapping(item, where)
    spec = LaserSpec(
        frame_id=reader.name(item, 'frame_id', where),
        pose=reader.pose(item, 'pose', where, MOUNT_OFFSET),
        min_angle=reader.number(item, 'min_angle', where, LASER_ANGLE),
        max_angle=reader.number(item, 'max_angle', where, LASER_ANGLE),
        min_range=reader.number(item, 'min_range', where, MIN_RANGE),
        max_range=reader.number(item, 'max_range', where, MAX_RANGE),
        num_rays=reader.count(item, 'num_rays', where, RAYS),
        frequency=reader.number(item, 'frequency', where, FREQUENCY),
        noise=reader.noise(item, where))
    if spec.max_angle < spec.min_angle:
        reader.fail(f'{where}.max_angle', f'{compact(spec.max_angle)} is below min_angle '
                    f'{compact(spec.min_angle)}')
    reader.check_ranges(spec, where)
    return spec


def _sonar(reader, item, where):
    item = reader.mapping(item, where)
    spec = SonarSpec(
        frame_id=reader.name(item, 'frame_id', where),
        pose=reader.pose(item, 'pose', where, MOUNT_OFFSET),
        cone_angle=reader.number(item, 'cone_angle', where, CONE_ANGLE),
        min_range=reader.number(item, 'min_range', where, MIN_RANGE),
        max_range=reader.number(item, 'max_range', where, MAX_RANGE),
        frequency=reader.number(item, 'frequency', where, FREQUENCY),
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
            self.fail(key or 'top level', f'expected a mapping, got {describe(value)}')
        return value

    def sequence(self, data, key, where):
        value = data.get(key) or []
        if not isinstance(value, list):
            self.fail(f'{where}.{key}', f'expected a list, got {describe(value)}')
        return value

    def number(self, data, key, where, bounds=FINITE):
        name = f'{where}.{key}' if where else key
        if key not in data:
            self.fail(name, 'missing')
        value = data[key]
        if not is_finite_number(value):
            self.fail(name, f'expected a finite number, got {describe(value)}')
        if not bounds.contains(value):
            self.fail(name, f'must be {bounds.text()}, got {compact(value)}')
        return float(value)

    def count(self, data, key, where, bounds):
        value = self.number(data, key, where, bounds)
        if value != int(value):
            self.fail(f'{where}.{key}', f'expected a whole number, got {compact(value)}')
        return int(value)

    def name(self, data, key, where, default=None):
        value = data.get(key, default)
        if not is_ros_name(value):
            self.fail(f'{where}.{key}', f'expected {ROS_NAME_RULE}, got {describe(value)}')
        return value

    def pose(self, data, key, where, position_bounds):
        name = f'{where}.{key}' if where else key
        pose = self.mapping(data.get(key, {'x': 0, 'y': 0, 'theta': 0}), name)
        return (self.number(pose, 'x', name, position_bounds),
                self.number(pose, 'y', name, position_bounds),
                self.number(pose, 'theta', name, HEADING))

    def noise(self, data, where):
        noise = self.mapping(data.get('noise') or {'mean': 0, 'std': 0}, f'{where}.noise')
        return Noise(self.number(noise, 'mean', f'{where}.noise', NOISE_MEAN),
                     self.number(noise, 'std', f'{where}.noise', NOISE_STD))

    def check_ranges(self, spec, where):
        if spec.max_range <= spec.min_range:
            self.fail(f'{where}.max_range', f'{compact(spec.max_range)} must exceed min_range '
                      f'{compact(spec.min_range)}')


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
    data = read_yaml(path, 'robot list', RobotFileError, MAX_LIST_BYTES)
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
        reader.fail(where, f'unknown keys {shorten(str(unknown))}; expected name, description, '
                    'pose')
    name = reader.name(item, 'name', where, default_name)
    description = default_description
    if 'description' in item:
        if not isinstance(item['description'], str):
            reader.fail(f'{where}.description', f'expected a file name, got '
                        f'{describe(item["description"])}')
        description = load_robot(os.path.join(folder, item['description']))
    pose = item.get('pose', list(description.initial_pose))
    if not isinstance(pose, list) or len(pose) != 3 or not all(map(is_finite_number, pose)):
        reader.fail(f'{where}.pose', f'expected [x, y, theta] as finite numbers, got '
                    f'{describe(pose)}')
    for axis, value, bounds in zip(('x', 'y', 'theta'), pose, (POSITION, POSITION, HEADING)):
        if not bounds.contains(value):
            reader.fail(f'{where}.pose', f'{axis} must be {bounds.text()}, got {compact(value)}')
    return RobotEntry(name, description, tuple(float(value) for value in pose))
