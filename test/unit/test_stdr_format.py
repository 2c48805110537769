"""
STDR's own robot layouts: its nested YAML and its XML, with files included by name.

Every file here is ours, written in STDR's layouts with the elements its files use: a small
robot like STDR's pandora (a laser, five sonars, one mounted past pi), given once flat, once
nested and once as XML that includes its sensors from a resource folder laid out as STDR's.
"""

from dataclasses import replace
import math

import pytest
from simple_robot_control.share import BUNDLED_RESOURCES, shared_file
from stdr_lite.core.robot_description import (load_robot, parse_robot, parse_robot_text,
                                              RobotFileError)
from stdr_lite.core.stdr_format import MAX_INCLUDE_DEPTH
import yaml

SONAR_MOUNTS = ((0.1, 0.0, 0.0), (0.0, 0.1, 1.5708), (0.0, -0.1, -1.5708),
                (-0.1, -0.1, 2.7925), (-0.1, 0.1, 3.49))
FLAT = {
    'initial_pose': {'x': 0.5, 'y': 0.25, 'theta': 0.0},
    'footprint': {'radius': 0.15},
    'sensors': {
        'lasers': [{'frame_id': 'laser_0', 'pose': {'x': 0.05, 'y': 0.0, 'theta': 0.0},
                    'min_angle': -2.0, 'max_angle': 2.0, 'min_range': 0.05, 'max_range': 5.0,
                    'num_rays': 400, 'frequency': 10, 'noise': {'mean': 0.0, 'std': 0.02}}],
        'sonars': [{'frame_id': f'sonar_{index}',
                    'pose': dict(zip('xy', mount[:2]), theta=mount[2]),
                    'cone_angle': 0.5, 'min_range': 0.2, 'max_range': 2.5, 'frequency': 5,
                    'noise': {'mean': 0.0, 'std': 0.01}}
                   for index, mount in enumerate(SONAR_MOUNTS)]}}
# The same robot as STDR's nested YAML writes it: a list under robot_specifications, every
# value spelled out (as pandora_robot.yaml has them), sensors taking STDR's default frame_ids.
NESTED = 'robot:\n  robot_specifications:\n' + ''.join(
    f'    - {line}\n' for line in (
        'initial_pose: {x: 0.5, y: 0.25, theta: 0}',
        'footprint: {footprint_specifications: {radius: 0.15, points: []}}',
        'laser: {laser_specifications: {max_angle: 2, min_angle: -2, max_range: 5, '
        'min_range: 0.05, num_rays: 400, frequency: 10, pose: {x: 0.05, y: 0, theta: 0}, '
        'noise: {noise_specifications: {noise_mean: 0, noise_std: 0.02}}}}',
        *(f'sonar: {{sonar_specifications: {{cone_angle: 0.5, max_range: 2.5, min_range: 0.2, '
          f'frequency: 5, pose: {{x: {x}, y: {y}, theta: {theta}}}, noise: '
          '{noise_specifications: {noise_mean: 0, noise_std: 0.01}}}}'
          for x, y, theta in SONAR_MOUNTS)))
SONAR = """<sonar>
  <sonar_specifications>
    <cone_angle>0.5</cone_angle>
    <max_range>2.5</max_range>
    <min_range>0.2</min_range>
    <frequency>5</frequency>
    <pose><x>0</x><y>0</y><theta>0</theta></pose>
    <noise><filename>noises/gauss.xml</filename></noise>
  </sonar_specifications>
</sonar>
"""
NOISE = ('<noise><noise_specifications><noise_mean>0</noise_mean><noise_std>0.01</noise_std>'
         '</noise_specifications></noise>')
LASER = """<laser>
  <laser_specifications>
    <max_angle>2</max_angle>
    <min_angle>-2</min_angle>
    <max_range>5</max_range>
    <min_range>0.05</min_range>
    <num_rays>400</num_rays>
    <noise><noise_specifications><noise_std>0.02</noise_std></noise_specifications></noise>
  </laser_specifications>
</laser>
"""
# The robot includes the sensors and overrides what differs, as pandora_robot.xml does.
XML_ROBOT = """<robot>
  <robot_specifications>
    <initial_pose><x>0.5</x><y>0.25</y><theta>0</theta></initial_pose>
    <footprint>
      <footprint_specifications>
        <radius>
          0.15
        </radius>
      </footprint_specifications>
    </footprint>
    <laser>
      <filename>
        laser_sensors/small_laser.xml
      </filename>
      <laser_specifications><pose><x>0.05</x></pose></laser_specifications>
    </laser>
""" + ''.join(f"""    <sonar>
      <filename>range_sensors/small_sonar.xml</filename>
      <sonar_specifications>
        <pose><x>{x}</x><y>{y}</y><theta>{theta}</theta></pose>
      </sonar_specifications>
    </sonar>
""" for x, y, theta in SONAR_MOUNTS) + """  </robot_specifications>
</robot>
"""


def wrapped(description):
    """Return the flat robot as it loads from STDR's layouts, which are marked as theirs."""
    return replace(parse_robot(yaml.safe_load(yaml.safe_dump(description)), 'flat.yaml'),
                   stdr_layout=True)


@pytest.fixture
def resources(tmp_path):
    """Give a resource folder in STDR's layout: robots/ beside laser_sensors/, ..."""
    for folder, name, text in (('laser_sensors', 'small_laser.xml', LASER),
                               ('range_sensors', 'small_sonar.xml', SONAR),
                               ('noises', 'gauss.xml', NOISE),
                               ('robots', 'small_robot.xml', XML_ROBOT),
                               ('robots', 'small_robot.yaml', NESTED)):
        (tmp_path / folder).mkdir(exist_ok=True)
        (tmp_path / folder / name).write_text(text)
    return tmp_path


def test_nested_yaml_gives_the_flat_description(resources):
    nested = load_robot(resources / 'robots' / 'small_robot.yaml')
    assert nested == wrapped(FLAT)
    assert nested.sonars[4].pose[2] == pytest.approx(3.49 - 2 * math.pi)


def test_xml_with_includes_gives_the_flat_description(resources):
    assert load_robot(resources / 'robots' / 'small_robot.xml') == wrapped(FLAT)


def test_includes_are_found_beside_the_including_file_and_on_the_search_path(tmp_path):
    (tmp_path / 'mine').mkdir()
    (tmp_path / 'mine' / 'robot.xml').write_text(XML_ROBOT)
    shared = tmp_path / 'course'
    for folder, name, text in (('laser_sensors', 'small_laser.xml', LASER),
                               ('range_sensors', 'small_sonar.xml', SONAR),
                               ('range_sensors/noises', 'gauss.xml', NOISE)):
        (shared / folder).mkdir(parents=True, exist_ok=True)
        (shared / folder / name).write_text(text)
    with pytest.raises(RobotFileError) as raised:
        load_robot(tmp_path / 'mine' / 'robot.xml')
    assert 'robot.xml:12: laser.filename laser_sensors/small_laser.xml: no such file' in str(
        raised.value)
    assert str(tmp_path / 'mine') in str(raised.value) and '\n' not in str(raised.value)
    # STDR's resources folder, the one above the robot file's, holds none of them: the
    # sensors are on the search path, and the sonar's noise beside the sonar file.
    assert load_robot(tmp_path / 'mine' / 'robot.xml', (shared,)) == wrapped(FLAT)


def test_a_resource_string_finds_its_includes_on_the_search_path(resources):
    text = (resources / 'robots' / 'small_robot.xml').read_text()
    assert parse_robot_text(text, 'resource_string', (resources,)) == wrapped(FLAT)


def test_stdr_defaults_fill_what_a_file_leaves_out():
    robot = parse_robot_text('<robot><robot_specifications><laser><laser_specifications/>'
                             '</laser><sonar><sonar_specifications/></sonar>'
                             '</robot_specifications></robot>', 'bare.xml')
    laser, = robot.lasers
    sonar, = robot.sonars
    assert robot.radius == 0.3 and robot.initial_pose == (0.0, 0.0, 0.0)
    assert (laser.frame_id, laser.min_angle, laser.max_angle, laser.num_rays,
            laser.max_range, laser.frequency) == ('laser_0', -1.57, 1.57, 180, 4.0, 10.0)
    assert (sonar.frame_id, sonar.cone_angle, sonar.max_range) == ('sonar_0', 1.0, 4.0)


def test_sensors_stdr_has_and_we_do_not_are_kept_by_name():
    robot = parse_robot_text(
        '<robot><robot_specifications><rfid_reader><rfid_reader_specifications><frame_id>tags'
        '</frame_id><angle_span>6.28</angle_span></rfid_reader_specifications></rfid_reader>'
        '<co2_sensor/><thermal_sensor/><sound_sensor/></robot_specifications></robot>',
        'sensing.xml')
    assert robot.unsimulated == ('rfid_reader tags', 'co2_sensor co2_sensor_0',
                                 'thermal_sensor thermal_sensor_0', 'sound_sensor sound_sensor_0')


def test_a_polygon_footprint_and_a_kinematic_model_are_read():
    robot = parse_robot_text("""
robot:
  robot_specifications:
    - footprint:
        footprint_specifications:
          points:
            - point: {x: -0.2, y: -0.2}
            - point: {x: 0.2, y: -0.2}
            - point: {x: 0.2, y: 0.2}
            - point: {x: -0.2, y: 0.2}
    - kinematic:
        kinematic_specifications:
          kinematic_model: omni
          kinematic_parameters: {a_uy_uy: 0.1, a_g_uy: 0.05}
""", 'square.yaml')
    assert robot.points == ((-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2))
    assert robot.radius == pytest.approx(math.hypot(0.2, 0.2))
    assert robot.kinematic.model == 'omni' and robot.kinematic.noisy


@pytest.mark.parametrize('text, message', [
    ('<robot><robot_specifications><wheels/></robot_specifications></robot>',
     'bad.xml:1: robot.robot_specifications: unknown element wheels (allowed: co2_sensor, '),
    ('<robot>\n<robot_specifications>\n<laser><laser_specifications><num_rays>many</num_rays>'
     '</laser_specifications></laser></robot_specifications></robot>',
     "bad.xml:3: laser[0].num_rays: expected a number, got 'many'"),
    ('<robot><robot_specifications>\n<laser>\n', 'bad.xml:3: robot file is not valid XML'),
    ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "aaaa">]>\n<robot/>',
     'bad.xml:2: robot file declares a DOCTYPE'),
    ('<robot><robot_specifications/></robot><robot/>', 'bad.xml:1: robot file is not valid '
     'XML (junk after document element)'),
    ('<laser/>', 'bad.xml: expected one robot element at the top, got laser'),
    ('<robot><robot_specifications><laser><filename>nowhere.xml</filename></laser>'
     '</robot_specifications></robot>', 'bad.xml:1: laser.filename nowhere.xml: no such file '
     '(looked in nowhere)'),
    ('<robot><robot_specifications><footprint><footprint_specifications><points><point><x>0'
     '</x></point></points></footprint_specifications></footprint></robot_specifications>'
     '</robot>', 'bad.xml: footprint.points: a polygon of 3 to 64 points, got 1'),
])
def test_a_file_we_cannot_read_is_one_line_naming_file_and_element(text, message):
    with pytest.raises(RobotFileError) as raised:
        parse_robot_text(text, 'bad.xml')
    assert message in str(raised.value) and '\n' not in str(raised.value)


def test_includes_that_never_end_are_refused(tmp_path):
    (tmp_path / 'robots').mkdir()
    (tmp_path / 'robots' / 'loop.xml').write_text(
        '<robot><robot_specifications><laser><filename>laser.xml</filename></laser>'
        '</robot_specifications></robot>')
    (tmp_path / 'robots' / 'laser.xml').write_text('<laser><filename>laser.xml</filename>'
                                                   '</laser>')
    with pytest.raises(RobotFileError) as raised:
        load_robot(tmp_path / 'robots' / 'loop.xml')
    assert (f'laser.xml:1: laser.filename laser.xml: files include each other more than '
            f'{MAX_INCLUDE_DEPTH} deep') in str(raised.value)


def test_an_included_file_must_hold_what_includes_it(tmp_path):
    (tmp_path / 'robots').mkdir()
    (tmp_path / 'robots' / 'robot.xml').write_text(
        '<robot><robot_specifications><sonar><filename>laser.xml</filename></sonar>'
        '</robot_specifications></robot>')
    (tmp_path / 'robots' / 'laser.xml').write_text(LASER)
    with pytest.raises(RobotFileError, match='sonar.filename laser.xml: that file holds laser, '
                       'not a sonar'):
        load_robot(tmp_path / 'robots' / 'robot.xml')


def test_the_bundled_turtlebot3_has_a_full_turn_laser_from_straight_ahead():
    robot = load_robot(shared_file('robots', 'turtlebot3_burger.xml'),
                       (shared_file(*BUNDLED_RESOURCES),))
    laser, = robot.lasers
    assert (laser.frame_id, laser.num_rays, laser.min_angle, laser.min_range,
            laser.max_range) == ('scan', 360, 0.0, 0.12, 3.5)
    assert (laser.max_angle - laser.min_angle) / (laser.num_rays - 1) == pytest.approx(
        math.radians(1.0))
    assert len(robot.points) == 4
