"""
What can be spawned, and reading what a spawn request asks for. No ROS here.

A resource is an STDR robot file (format stdr_robot_yaml, as robot_description takes) or a
circular obstacle (format stdr_lite_obstacle_yaml: {obstacle: {radius: m, moving: bool}}),
given as text or by URI: a file's path or file:// URI, or the name of a bundled spawnable.
"""

from dataclasses import dataclass
import os
from urllib.parse import unquote, urlparse

from simple_robot_control.input_files import parse_yaml, read_yaml
from simple_robot_control.validation import Bounds, describe, is_finite_number, shorten
from stdr_lite.core.robot_description import parse_robot, RobotDescription, RobotFileError

ROBOT_FORMAT = 'stdr_robot_yaml'
OBSTACLE_FORMAT = 'stdr_lite_obstacle_yaml'
SPAWN_FORMATS = (ROBOT_FORMAT, OBSTACLE_FORMAT)
OBSTACLE_RADIUS = Bounds(0.0, 0.5, low_open=True)


class SpawnResourceError(ValueError):
    """
    A resource that cannot be spawned; kind says why, as the standard's spawn results do.

    kind is one of no_resource, unsupported_format, missing_assets, parse_error.
    """

    def __init__(self, kind, message):
        super().__init__(message)
        self.kind = kind


@dataclass(frozen=True)
class ObstacleSpec:
    """A circular obstacle: its radius, and whether it may be set moving."""

    radius: float
    moving: bool = False


def path_of(uri: str, bundled: dict) -> str:
    """Return the file a URI names: a bundled spawnable's, a file:// URI's, or a plain path."""
    if uri in bundled:
        return bundled[uri]
    parsed = urlparse(uri)
    if parsed.scheme == 'file':
        return unquote(parsed.path)
    if parsed.scheme:
        raise SpawnResourceError('unsupported_format', f'{shorten(uri)}: only file paths, '
                                 'file:// URIs and the bundled spawnables '
                                 f'({", ".join(sorted(bundled))}) can be spawned')
    return uri


def load_resource(uri: str, resource_string: str,
                  bundled: dict) -> RobotDescription | ObstacleSpec:
    """Read what a spawn request names (uri first, else resource_string), or raise."""
    if uri:
        path = path_of(uri, bundled)
        if not path.endswith(('.yaml', '.yml')):
            raise SpawnResourceError('unsupported_format', f'{shorten(uri)}: spawn formats are '
                                     f'{" and ".join(SPAWN_FORMATS)} (YAML files)')
        if not os.path.exists(path):
            raise SpawnResourceError('missing_assets', f'{shorten(uri)}: no such file')
        try:
            return parse_resource(read_yaml(path, 'spawn resource', RobotFileError), path)
        except RobotFileError as error:
            raise SpawnResourceError('parse_error', str(error)) from None
    if resource_string:
        try:
            return parse_resource(parse_yaml(resource_string, 'resource_string', 'spawn resource',
                                             RobotFileError), 'resource_string')
        except RobotFileError as error:
            raise SpawnResourceError('parse_error', str(error)) from None
    raise SpawnResourceError('no_resource', 'give a uri or a resource_string')


def parse_resource(data: object, source: str) -> RobotDescription | ObstacleSpec:
    """Return the obstacle or the robot description that parsed YAML describes."""
    if isinstance(data, dict) and 'obstacle' in data:
        return _obstacle(data, source)
    return parse_robot(data, source)


def _obstacle(data, source):
    if set(data) != {'obstacle'} or not isinstance(data['obstacle'], dict):
        raise RobotFileError(f'{source}: expected {{obstacle: {{radius: m, moving: bool}}}}')
    fields = data['obstacle']
    unknown = sorted(set(fields) - {'radius', 'moving'})
    if unknown:
        raise RobotFileError(f'{source}: obstacle: unknown keys {shorten(str(unknown))}; '
                             'expected radius, moving')
    radius = fields.get('radius')
    if not is_finite_number(radius) or not OBSTACLE_RADIUS.contains(radius):
        raise RobotFileError(f'{source}: obstacle.radius must be {OBSTACLE_RADIUS.text()} m, '
                             f'got {describe(radius)}')
    moving = fields.get('moving', False)
    if not isinstance(moving, bool):
        raise RobotFileError(f'{source}: obstacle.moving must be true or false, got '
                             f'{describe(moving)}')
    return ObstacleSpec(float(radius), moving)
