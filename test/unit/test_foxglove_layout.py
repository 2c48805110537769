"""The bundled Foxglove layout: the lab's scene, in the file format the Foxglove app imports."""

import json
from pathlib import Path

import pytest
from stdr_lite.core.loading import robot_file
from stdr_lite.core.robot_description import load_robot
from waypoint_lab.foxglove_layout import app_layout, lab_layout, LASERS, layout_text, SONARS

BUNDLED = Path(__file__).resolve().parents[2] / 'config' / 'foxglove_lab_layout.json'


def leaves(tree):
    """Yield the panel ids of the app's layout tree, left to right."""
    if isinstance(tree, str):
        yield tree
    else:
        yield from leaves(tree['first'])
        yield from leaves(tree['second'])


def test_the_bundled_file_is_the_layout_made_now():
    assert BUNDLED.read_text() == layout_text(), (
        'run: python -m waypoint_lab.foxglove_layout > config/foxglove_lab_layout.json')


def test_the_file_has_the_apps_layout_format():
    """Keys and tree as the app exports a layout (Foxglove Studio's LayoutData)."""
    layout = json.loads(BUNDLED.read_text())
    assert set(layout) == {'configById', 'globalVariables', 'userNodes', 'playbackConfig',
                           'layout'}
    assert list(leaves(layout['layout'])) == list(layout['configById'])
    assert all(panel_id.count('!') == 1 for panel_id in layout['configById'])
    # The scene takes two thirds of the width, the side's three panels a third of its height each.
    assert layout['layout']['direction'] == 'row'
    assert layout['layout']['splitPercentage'] == pytest.approx(200 / 3)
    side = layout['layout']['second']
    assert (side['direction'], side['splitPercentage']) == ('column', pytest.approx(100 / 3))
    assert side['second']['splitPercentage'] == pytest.approx(50)


def test_the_layout_shows_the_lab_and_drives_its_robot():
    layout = app_layout(lab_layout())
    by_type = {panel_id.split('!')[0]: config
               for panel_id, config in layout['configById'].items()}
    assert set(by_type) == {'3D', 'RawMessages', 'Teleop', 'Plot'}
    assert by_type['3D']['followTf'] == 'map'
    assert by_type['3D']['foxglovePanelTitle'] == 'The lab room'
    assert {'/map', '/waypoints', '/robot0/laser_0'} <= set(by_type['3D']['topics'])
    assert by_type['RawMessages']['topicPath'] == '/robot_status.data'
    assert by_type['Teleop']['topic'] == '/robot0/cmd_vel'
    assert [series['value'] for series in by_type['Plot']['paths']] == [
        f'/robot0/sonar_{index}.range' for index in range(5)]


def test_the_layouts_sensors_are_the_lab_robots():
    description = load_robot(robot_file('lab_robot'))
    assert LASERS == tuple(laser.frame_id for laser in description.lasers)
    assert SONARS == tuple(sonar.frame_id for sonar in description.sonars)
