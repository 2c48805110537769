"""
Robot descriptions: footprint, kinematics, initial pose, lasers and sonars, in STDR's layouts.

A robot file is in one of STDR's layouts, its nested YAML (`robot: robot_specifications: [...]`)
or its XML, both with files included by name (stdr_format.py), or in the flat YAML layout below.
Every layout reaches parse_robot as the flat one, so one set of rules checks them all:

    initial_pose: {x, y, theta}
    footprint: {radius: m, points: [[x, y], ...]}        # points make a polygon, else a circle
    kinematic: {model: ideal | omni, parameters: {a_ux_ux: ..., a_g_w: ...}}
    sensors:
      lasers: [{frame_id, pose: {x, y, theta}, min_angle, max_angle, min_range, max_range,
                num_rays, frequency, noise: {mean, std}}, ...]
      sonars: [{frame_id, pose, cone_angle, min_range, max_range, frequency, noise}, ...]
      rfid_readers, co2_sensors, thermal_sensors, sound_sensors: [{frame_id}, ...]

Lengths are metres, angles radians, frequencies hertz. The sensors STDR knows but stdr_lite does
not simulate are kept by name (unsimulated), never refused and never dropped without a word.
"""

from dataclasses import dataclass, replace
import math
import os

from simple_robot_control.input_files import MAX_DESCRIPTION_BYTES, parse_yaml, read_text
from simple_robot_control.pose import wrap_angle
from simple_robot_control.validation import Bounds, compact, FINITE
from stdr_lite.core.fields import FieldReader, RobotFileError
from stdr_lite.core.footprints import polygon_problem
from stdr_lite.core.stdr_format import (flat_from_xml, flat_from_yaml, is_stdr_layout,
                                        KINEMATIC_PARAMETERS, StdrFileError)

# What a description may hold: generous for any small robot, finite everywhere, so a typo such
# as a frequency of 1e12 is refused where it is read rather than failing in a later step.
MAX_RADIUS = 5.0
RADIUS = Bounds(0.0, MAX_RADIUS, low_open=True)
FOOTPRINT_POINT = Bounds(-MAX_RADIUS, MAX_RADIUS)
MAX_POLYGON_POINTS = 64
MOUNT_OFFSET = Bounds(-10.0, 10.0)
HEADING = Bounds(-2.0 * math.pi, 2.0 * math.pi)
POSITION = Bounds(-1e6, 1e6)
# A laser spans at most a turn, anywhere in two turns either way (0 to 2*pi, as TurtleBot3's).
LASER_ANGLE = Bounds(-2.0 * math.pi, 2.0 * math.pi)
FULL_TURN = 2.0 * math.pi + 1e-9
CONE_ANGLE = Bounds(0.0, math.pi, low_open=True)
MIN_RANGE = Bounds(0.0, 1000.0)
MAX_RANGE = Bounds(0.0, 1000.0, low_open=True)
RAYS = Bounds(1, 10000)
FREQUENCY = Bounds(0.001, 1000.0)
NOISE_MEAN = Bounds(-1.0, 1.0)
NOISE_STD = Bounds(0.0, 1.0)
MOTION_NOISE = Bounds(0.0, 100.0)
KINEMATIC_MODELS = ('ideal', 'omni')
# Each sensor is a topic of its own, and endpoints are what a swarm costs most: twice the
# sensors of STDR's most equipped robot (khepera3, 14).
MAX_SENSORS = 32
# A robot's own topics, /<robot>/<name>: a sensor's topic is /<robot>/<frame_id>, so no sensor
# may take one of these names.
ROBOT_TOPICS = ('cmd_vel', 'odom', 'ground_truth', 'stall', 'initialpose')
# The sensors STDR has that stdr_lite does not simulate, by their flat key and their name.
UNSIMULATED_KINDS = {'rfid_readers': 'rfid_reader', 'co2_sensors': 'co2_sensor',
                     'thermal_sensors': 'thermal_sensor', 'sound_sensors': 'sound_sensor'}


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
class Kinematic:
    """
    How commands move the robot: STDR's ideal (a unicycle) or omni model, and its motion noise.

    parameters are STDR's a_<row>_<column> (rows ux, uy, w, g; columns ux, uy, w), in the order
    of KINEMATIC_PARAMETERS: each command's u_x is taken as u_x + N(0, a_ux_ux u_x^2 + a_ux_uy
    u_y^2 + a_ux_w w^2), and likewise u_y, w and an extra turn g.
    """

    model: str = 'ideal'
    parameters: tuple = (0.0,) * len(KINEMATIC_PARAMETERS)

    @property
    def noisy(self) -> bool:
        return any(self.parameters)


@dataclass(frozen=True)
class RobotDescription:
    """
    A robot's footprint, sensors and kinematics.

    radius is the footprint's: the circle's, or for a polygon (points, in the robot's frame)
    the distance from the robot's centre to its farthest corner. stdr_layout says the file was
    in one of STDR's layouts (XML, nested YAML), whose noise fields STDR itself never applies.
    """

    radius: float
    initial_pose: tuple
    lasers: tuple = ()
    sonars: tuple = ()
    points: tuple = ()
    kinematic: Kinematic = Kinematic()
    unsimulated: tuple = ()
    stdr_layout: bool = False

    @property
    def has_sensor_noise(self) -> bool:
        return any(spec.noise != Noise() for spec in self.lasers + self.sonars)


def load_robot(path: str | os.PathLike, search_path: tuple = ()) -> RobotDescription:
    """Read and check a robot file in any of its layouts (.xml, or YAML nested or flat)."""
    path = os.fspath(path)
    text = read_text(path, 'robot file', RobotFileError, MAX_DESCRIPTION_BYTES)
    return parse_robot_text(text, path, search_path, in_file=True)


def parse_robot_text(text: str, source: str, search_path: tuple = (),
                     in_file: bool = False) -> RobotDescription:
    """Read a robot description from text in any layout; source names it in complaints."""
    if not text.lstrip().startswith('<'):
        return robot_from_yaml(parse_yaml(text, source, 'robot file', RobotFileError), source,
                               search_path, in_file)
    try:
        flat = flat_from_xml(text, source, search_path, in_file)
    except StdrFileError as error:
        raise RobotFileError(str(error)) from None
    return replace(parse_robot(flat, source), stdr_layout=True)


def robot_from_yaml(data: object, source: str, search_path: tuple = (),
                    in_file: bool = False) -> RobotDescription:
    """Check a robot read from YAML, in STDR's nested layout or the flat one."""
    stdr_layout = is_stdr_layout(data)
    try:
        if stdr_layout:
            data = flat_from_yaml(data, source, search_path, in_file)
    except StdrFileError as error:
        raise RobotFileError(str(error)) from None
    return replace(parse_robot(data, source), stdr_layout=stdr_layout)


def parse_robot(data: object, source: str = '<robot>') -> RobotDescription:
    """Check a robot description in the flat layout; return a RobotDescription."""
    reader = FieldReader(source)
    data = reader.mapping(data, '')
    footprint = reader.mapping(data.get('footprint', {}), 'footprint')
    points = _polygon(reader, reader.sequence(footprint, 'points', 'footprint'))
    radius = (max(math.hypot(x, y) for x, y in points) if points
              else reader.number(footprint, 'radius', 'footprint', RADIUS))
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
    return RobotDescription(radius, reader.pose(data, 'initial_pose', '', POSITION, HEADING),
                            lasers, sonars, points, _kinematic(reader, data),
                            _unsimulated(reader, data, sensors))


def _polygon(reader, items):
    if not items:
        return ()
    if not 3 <= len(items) <= MAX_POLYGON_POINTS:
        reader.fail('footprint.points', f'a polygon of 3 to {MAX_POLYGON_POINTS} points, got '
                    f'{len(items)}')
    points = []
    for index, item in enumerate(items):
        where = f'footprint.points[{index}]'
        if isinstance(item, list) and len(item) == 2:
            item = {'x': item[0], 'y': item[1]}
        item = reader.mapping(item, where)
        points.append((reader.number(item, 'x', where, FOOTPRINT_POINT),
                       reader.number(item, 'y', where, FOOTPRINT_POINT)))
    problem = polygon_problem(points)
    if problem is not None:
        reader.fail('footprint.points', problem)
    radius = max(math.hypot(x, y) for x, y in points)
    if not RADIUS.contains(radius):
        reader.fail('footprint.points', f'the farthest corner must be {RADIUS.text()} m from '
                    f'the centre, got {compact(radius)}')
    return tuple(points)


def _kinematic(reader, data):
    if 'kinematic' not in data:
        return Kinematic()
    kinematic = reader.mapping(data['kinematic'], 'kinematic')
    unknown = sorted(set(kinematic) - {'model', 'parameters', 'type'})
    if unknown:
        reader.fail('kinematic', f'unknown {unknown[0]!r} (expected model, parameters)')
    # The early flat layout names the model type, empty for the ideal one.
    model = reader.choice(kinematic, 'model', 'kinematic', KINEMATIC_MODELS,
                          kinematic.get('type') or 'ideal')
    parameters = reader.mapping(kinematic.get('parameters') or {}, 'kinematic.parameters')
    unknown = sorted(set(parameters) - set(KINEMATIC_PARAMETERS))
    if unknown:
        reader.fail('kinematic.parameters', f'unknown {unknown[0]!r} (STDR names them '
                    'a_ux_ux ... a_g_w)')
    return Kinematic(model, tuple(
        reader.number(parameters, name, 'kinematic.parameters', MOTION_NOISE)
        if name in parameters else 0.0 for name in KINEMATIC_PARAMETERS))


def _unsimulated(reader, data, sensors):
    """Name the sensors kept but not simulated: from the flat keys, or STDR's elements."""
    names = []
    for key, kind in UNSIMULATED_KINDS.items():
        for index, item in enumerate(reader.sequence(sensors, key, 'sensors')):
            item = reader.mapping(item, f'sensors.{key}[{index}]')
            names.append(f'{kind} {item.get("frame_id", f"{kind}_{index}")}')
    names += [str(name) for name in reader.sequence(data, 'unsimulated', '')]
    return tuple(names)


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


def _mount(reader, item, where):
    """Return a sensor's mount: any finite heading, wrapped, as STDR reads it."""
    x, y, theta = reader.pose(item, 'pose', where, MOUNT_OFFSET, FINITE)
    return x, y, wrap_angle(theta)


def _noise(reader, item, where):
    noise = reader.mapping(item.get('noise') or {'mean': 0, 'std': 0}, f'{where}.noise')
    return Noise(reader.number(noise, 'mean', f'{where}.noise', NOISE_MEAN),
                 reader.number(noise, 'std', f'{where}.noise', NOISE_STD))


def _laser(reader, item, where):
    item = reader.mapping(item, where)
    spec = LaserSpec(
        frame_id=reader.name(item, 'frame_id', where),
        pose=_mount(reader, item, where),
        min_angle=reader.number(item, 'min_angle', where, LASER_ANGLE),
        max_angle=reader.number(item, 'max_angle', where, LASER_ANGLE),
        min_range=reader.number(item, 'min_range', where, MIN_RANGE),
        max_range=reader.number(item, 'max_range', where, MAX_RANGE),
        num_rays=reader.count(item, 'num_rays', where, RAYS),
        frequency=reader.number(item, 'frequency', where, FREQUENCY),
        noise=_noise(reader, item, where))
    if spec.max_angle < spec.min_angle:
        reader.fail(f'{where}.max_angle', f'{compact(spec.max_angle)} is below min_angle '
                    f'{compact(spec.min_angle)}')
    if spec.max_angle - spec.min_angle > FULL_TURN:
        reader.fail(f'{where}.max_angle', f'a laser spans at most a full turn (2 pi), got '
                    f'{compact(spec.max_angle - spec.min_angle)} rad')
    _check_ranges(reader, spec, where)
    return spec


def _sonar(reader, item, where):
    item = reader.mapping(item, where)
    spec = SonarSpec(
        frame_id=reader.name(item, 'frame_id', where),
        pose=_mount(reader, item, where),
        cone_angle=reader.number(item, 'cone_angle', where, CONE_ANGLE),
        min_range=reader.number(item, 'min_range', where, MIN_RANGE),
        max_range=reader.number(item, 'max_range', where, MAX_RANGE),
        frequency=reader.number(item, 'frequency', where, FREQUENCY),
        noise=_noise(reader, item, where))
    _check_ranges(reader, spec, where)
    return spec


def _check_ranges(reader, spec, where):
    if spec.max_range <= spec.min_range:
        reader.fail(f'{where}.max_range', f'{compact(spec.max_range)} must exceed min_range '
                    f'{compact(spec.min_range)}')


@dataclass(frozen=True)
class RobotEntry:
    """One robot of a world: its name, its description, and where it starts."""

    name: str
    description: RobotDescription
    pose: tuple
