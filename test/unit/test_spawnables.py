"""Spawn resources: robots and obstacles by bundled name, path, file URI or text."""

from pathlib import Path
import re

import pytest

from simple_robot_control.share import shared_file
from stdr_lite.core.robot_description import RobotDescription
from stdr_lite.core.spawnables import load_resource, ObstacleSpec, SpawnResourceError

BUNDLED = {'lab_robot': shared_file('robots', 'lab_robot.yaml'),
           'obstacle': shared_file('obstacles', 'obstacle.yaml'),
           'moving_obstacle': shared_file('obstacles', 'moving_obstacle.yaml')}


def test_bundled_spawnables_by_name():
    assert isinstance(load_resource('lab_robot', '', BUNDLED), RobotDescription)
    assert load_resource('obstacle', '', BUNDLED) == ObstacleSpec(0.25, False)
    assert load_resource('moving_obstacle', 'ignored', BUNDLED) == ObstacleSpec(0.25, True)


def test_files_by_path_or_uri_and_text():
    path = BUNDLED['lab_robot']
    assert load_resource(path, '', BUNDLED).radius == 0.2
    assert load_resource(Path(path).as_uri(), '', BUNDLED).radius == 0.2
    assert load_resource(f'file://localhost{path}', '', BUNDLED).radius == 0.2
    assert load_resource('', 'footprint: {radius: 0.3}', BUNDLED).radius == 0.3
    assert load_resource('', '{obstacle: {radius: 0.4, moving: true}}', BUNDLED) == (
        ObstacleSpec(0.4, True))


@pytest.mark.parametrize('uri, text, kind, message', [
    ('', '', 'no_resource', 'give a uri or a resource_string'),
    ('model.sdf', '', 'unsupported_format', 'spawn formats are stdr_robot_yaml, stdr_robot_xml'),
    ('https://example.org/robot.yaml', '', 'unsupported_format', 'only file paths'),
    ('/no/such/robot.yaml', '', 'missing_assets', 'no such file'),
    ('file://otherhost' + BUNDLED['lab_robot'], '', 'unsupported_format',
     'names a file on otherhost, another machine; only local files'),
    ('', 'footprint: {radius: -1}', 'parse_error', 'footprint.radius: must be in'),
    ('', '{obstacle: {radius: 9}}', 'parse_error', 'obstacle.radius must be in (0, 0.5] m'),
    ('', '{obstacle: {radius: 0.2, moving: maybe}}', 'parse_error', 'true or false'),
    ('', 'robot: [unclosed', 'parse_error', 'not valid YAML'),
])
def test_what_cannot_be_spawned_says_why(uri, text, kind, message):
    with pytest.raises(SpawnResourceError, match=re.escape(message)) as raised:
        load_resource(uri, text, BUNDLED)
    assert raised.value.kind == kind
