"""
What can be spawned, and reading what a spawn request asks for. No ROS here.

A resource is an STDR robot file (formats stdr_robot_yaml and stdr_robot_xml: any layout
robot_description takes) or a circular obstacle (format stdr_lite_obstacle_yaml:
{obstacle: {radius: m, moving: bool}}), given as text or by URI: a file's path or file:// URI,
or the name of a bundled spawnable.
"""

from dataclasses import dataclass
import os
from urllib.parse import unquote, urlparse

from simple_robot_control.input_files import MAX_DESCRIPTION_BYTES, parse_yaml, read_text
from simple_robot_control.validation import Bounds, describe, is_finite_number, shorten
from stdr_lite.core.robot_description import (parse_robot_text, robot_from_yaml,
                                              RobotDescription, RobotFileError)

SPAWN_FORMATS = ('stdr_robot_yaml', 'stdr_robot_xml', 'stdr_lite_obstacle_yaml')
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
    if parsed.scheme == 'file' and parsed.netloc not in ('', 'localhost'):
        raise SpawnResourceError('unsupported_format', f'{shorten(uri)}: names a file on '
                                 f'{shorten(parsed.netloc)}, another machine; only local files '
                                 '(file:///path or file://localhost/path) are read')
    if parsed.scheme == 'file':
        return unquote(parsed.path)
    if parsed.scheme:
        raise SpawnResourceError('unsupported_format', f'{shorten(uri)}: only file paths, '
                                 'file:// URIs and the bundled spawnables '
                                 f'({", ".join(sorted(bundled))}) can be spawned')
    return uri


def load_resource(uri: str, resource_string: str, bundled: dict,
                  search_path: tuple = ()) -> RobotDescription | ObstacleSpec:
    """
    Read what a spawn request names (uri first, else resource_string), or raise.

    A robot may be in any layout a robot file may (robot_description.py); its includes are
    looked for in search_path, after STDR's own places when it comes from a file.
    """
    if uri:
        path = path_of(uri, bundled)
        if not path.endswith(('.yaml', '.yml', '.xml')):
            raise SpawnResourceError('unsupported_format', f'{shorten(uri)}: spawn formats are '
                                     f'{", ".join(SPAWN_FORMATS)} (YAML or XML files)')
        if not os.path.exists(path):
            raise SpawnResourceError('missing_assets', f'{shorten(uri)}: no such file')
        try:
            text = read_text(path, 'spawn resource', RobotFileError, MAX_DESCRIPTION_BYTES)
            return parse_resource(text, path, search_path, in_file=True)
        except RobotFileError as error:
            raise SpawnResourceError('parse_error', str(error)) from None
    if resource_string:
        try:
            return parse_resource(resource_string, 'resource_string', search_path, in_file=False)
        except RobotFileError as error:
            raise SpawnResourceError('parse_error', str(error)) from None
    raise SpawnResourceError('no_resource', 'give a uri or a resource_string')


def parse_resource(text: str, source: str, search_path: tuple = (),
                   in_file: bool = False) -> RobotDescription | ObstacleSpec:
    """Return the obstacle or the robot that a resource's text describes."""
    if len(text) > MAX_DESCRIPTION_BYTES:
        raise RobotFileError(f'{source}: spawn resource is too large ({len(text):,} characters; '
                             f'at most {MAX_DESCRIPTION_BYTES:,})')
    if not text.lstrip().startswith('<'):
        data = parse_yaml(text, source, 'spawn resource', RobotFileError)
        if isinstance(data, dict) and 'obstacle' in data:
            return _obstacle(data, source)
        return robot_from_yaml(data, source, search_path, in_file)
    return parse_robot_text(text, source, search_path, in_file)


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
