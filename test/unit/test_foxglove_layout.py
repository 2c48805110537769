"""The bundled Foxglove layout is what Foxglove's layout types make of the lab's scene."""

import json
from pathlib import Path

from stdr_lite.core.loading import robot_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.foxglove_layout import lab_layout, LASERS, layout_text, SONARS

BUNDLED = Path(__file__).resolve().parents[2] / 'config' / 'foxglove_lab_layout.json'


def panels(content):
    """Yield every panel of a layout's content, depth first."""
    if content['type'] == 'panel':
        yield content
    for item in content.get('items', []):
        yield from panels(item['content'])


def test_the_bundled_file_is_the_layout_made_now():
    assert BUNDLED.read_text() == layout_text(), (
        'run: python -m waypoint_lab.foxglove_layout > config/foxglove_lab_layout.json')


def test_the_layout_shows_the_lab_and_drives_its_robot():
    layout = json.loads(lab_layout().to_json())
    by_type = {panel['panelType']: panel['config'] for panel in panels(layout['content'])}
    assert set(by_type) == {'ThreeDee', 'RawMessages', 'Teleop', 'Plot'}
    assert by_type['ThreeDee']['followTf'] == 'map'
    assert {'/map', '/waypoints', '/robot0/laser_0'} <= set(by_type['ThreeDee']['topics'])
    assert by_type['RawMessages']['topicPath'] == '/robot_status.data'
    assert by_type['Teleop']['topic'] == '/robot0/cmd_vel'
    assert [series['value'] for series in by_type['Plot']['paths']] == [
        f'/robot0/sonar_{index}.range' for index in range(5)]


def test_the_layouts_sensors_are_the_lab_robots():
    description = load_robot(robot_file('lab_robot'))
    assert LASERS == tuple(laser.frame_id for laser in description.lasers)
    assert SONARS == tuple(sonar.frame_id for sonar in description.sonars)
