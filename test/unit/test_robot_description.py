"""Robot files in the flat layout: what loads, and one-line errors for what does not."""

import math

import pytest
from simple_robot_control.share import shared_file
from stdr_lite.core.robot_description import (Kinematic, load_robot, Noise, parse_robot,
                                              RobotFileError)
import yaml

# The flat layout (STDR's early development one, kept as ours; the values are ours).
FLAT_ROBOT = """
initial_pose: {x: 1.5, y: 2.5, theta: 0.5}
footprint: {radius: 0.15, points: []}
kinematic: {type: ""}
sensors:
  lasers:
    - {max_angle: 2.35, min_angle: -2.35, max_range: 4, min_range: 0, num_rays: 270,
       noise: {mean: 0.5, std: 0.2}, frequency: 10, frame_id: laser_0,
       pose: {x: 0.1, y: 0, theta: 0}}
  sonars:
    - {max_range: 3, min_range: 0.3, cone_angle: 0.52, noise: {mean: 0, std: 0},
       frequency: 5, frame_id: sonar_0, pose: {x: 0, y: 0.1, theta: 1.57}}
  rfids: []
"""


def test_flat_robot_file_loads(tmp_path):
    path = tmp_path / 'pandora.yaml'
    path.write_text(FLAT_ROBOT)
    robot = load_robot(path)
    assert robot.radius == 0.15 and robot.initial_pose == (1.5, 2.5, 0.5)
    laser, = robot.lasers
    assert (laser.frame_id, laser.num_rays, laser.min_angle, laser.max_range) == (
        'laser_0', 270, -2.35, 4.0)
    assert laser.noise == Noise(0.5, 0.2) and laser.pose == (0.1, 0.0, 0.0)
    sonar, = robot.sonars
    assert (sonar.frame_id, sonar.cone_angle, sonar.frequency) == ('sonar_0', 0.52, 5.0)


def test_bundled_lab_robot_is_the_lab_s():
    robot = load_robot(shared_file('robots', 'lab_robot.yaml'))
    laser, = robot.lasers
    assert robot.radius == 0.2
    assert (laser.num_rays, laser.min_range, laser.max_range, laser.frequency) == (
        667, 0.06, 4.09, 10.0)
    assert laser.max_angle == pytest.approx(math.radians(120), abs=1e-4) == -laser.min_angle
    assert robot.sonars and all(
        (sonar.cone_angle, sonar.min_range, sonar.max_range) == (0.87, 0.15, 3.0)
        for sonar in robot.sonars)


def edited(path_and_value):
    data = yaml.safe_load(FLAT_ROBOT)
    path, value = path_and_value
    node = data
    for key in path[:-1]:
        node = node[key]
    if value is None:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return data


@pytest.mark.parametrize('change, message', [
    ((('footprint', 'radius'), -1), 'footprint.radius: must be in (0, 5], got -1'),
    ((('footprint', 'radius'), 1e6), 'footprint.radius: must be in (0, 5], got 1000000'),
    ((('footprint', 'radius'), None), 'footprint.radius: missing'),
    ((('footprint', 'points'), [[0, 0], [1, 0]]), 'footprint.points: a polygon of 3 to 64 '
     'points, got 2'),
    ((('footprint', 'points'), [[0, 0], [1, 1], [1, 0], [0, 1]]), 'footprint.points: edges 0 '
     'and 2 cross'),
    ((('footprint', 'points'), [[0, 0], [1, 0], [2, 0]]), 'footprint.points: the corners '
     'enclose no area'),
    ((('footprint', 'points'), [[0, 0], [6, 0], [0, 1]]), 'footprint.points[1].x: must be in '
     '[-5, 5], got 6'),
    ((('sensors', 'lasers', 0, 'max_angle'), 4.0), 'sensors.lasers[0].max_angle: a laser spans '
     'at most a full turn (2 pi), got 6.35 rad'),
    ((('sensors', 'lasers', 0, 'pose', 'theta'), float('inf')), 'sensors.lasers[0].pose.theta: '
     'expected a finite number'),
    ((('kinematic',), {'model': 'tank'}), 'kinematic.model: expected one of ideal, omni'),
    ((('kinematic',), {'parameters': {'a_x': 1}}), "kinematic.parameters: unknown 'a_x'"),
    ((('kinematic',), {'parameters': {'a_ux_ux': -1}}), 'kinematic.parameters.a_ux_ux: must be '
     'in [0, 100], got -1'),
    ((('sensors', 'lasers', 0, 'num_rays'), 2.5), 'sensors.lasers[0].num_rays: expected a '
     'whole number'),
    ((('sensors', 'lasers', 0, 'max_range'), 'far'),
     "sensors.lasers[0].max_range: expected a finite number, got 'far'"),
    ((('sensors', 'sonars', 0, 'max_range'), 0.2), 'sensors.sonars[0].max_range: 0.2 must '
     'exceed min_range 0.3'),
    ((('sensors', 'sonars', 0, 'noise'), {'mean': 0, 'std': -1}),
     'sensors.sonars[0].noise.std: must be in [0, 1], got -1'),
    ((('sensors', 'lasers', 0, 'frequency'), 1e12),
     'sensors.lasers[0].frequency: must be in [0.001, 1000], got 1e+12'),
    ((('sensors', 'lasers', 0, 'frequency'), 1e-300),
     'sensors.lasers[0].frequency: must be in [0.001, 1000], got 1e-300'),
    ((('sensors', 'lasers', 0, 'num_rays'), 10 ** 9),
     'sensors.lasers[0].num_rays: must be in [1, 10000], got 1000000000'),
    ((('sensors', 'lasers', 0, 'min_angle'), -7), 'sensors.lasers[0].min_angle: must be in'),
    ((('sensors', 'sonars', 0, 'cone_angle'), 0), 'sensors.sonars[0].cone_angle: must be in'),
    ((('sensors', 'sonars', 0, 'max_range'), 1e308), 'sensors.sonars[0].max_range: must be in'),
    ((('sensors', 'lasers', 0, 'frame_id'), 'laser 0'), 'sensors.lasers[0].frame_id: expected '
     'a ROS name'),
    ((('initial_pose', 'theta'), float('nan')), 'initial_pose.theta: expected a finite number'),
    ((('sensors', 'lasers', 0, 'frame_id'), 'odom'),
     "sensors.lasers[0].frame_id: 'odom' names one of the robot topics"),
    ((('sensors', 'sonars', 0, 'frame_id'), 'laser_0'),
     "sensors.sonars[0].frame_id: 'laser_0' is the frame_id of sensors.lasers[0] too"),
    ((('sensors', 'sonars'), [{'frame_id': f'sonar_{k}', 'cone_angle': 0.5, 'min_range': 0.1,
                               'max_range': 3, 'frequency': 10} for k in range(33)]),
     'sensors: 34 sensors; a robot carries at most 32'),
])
def test_bad_robot_is_one_line_naming_the_key(change, message):
    with pytest.raises(RobotFileError) as raised:
        parse_robot(edited(change), 'robot.yaml')
    assert f'robot.yaml: {message}' in str(raised.value)
    assert '\n' not in str(raised.value)


def test_a_wrong_file_is_refused_without_echoing_its_contents():
    contents = 'root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin'
    with pytest.raises(RobotFileError) as raised:
        parse_robot(contents, '/etc/passwd')
    assert str(raised.value) == ('/etc/passwd: top level: expected a mapping, got a text of '
                                 f'{len(contents)} characters')


def test_polygons_mounts_kinematics_and_unsimulated_sensors_are_kept():
    data = edited((('footprint', 'points'), [[-0.2, -0.1], [0.3, -0.1], [0.3, 0.1], [-0.2, 0.1]]))
    data['sensors']['lasers'][0].update(min_angle=0.0, max_angle=2 * math.pi)
    data['sensors']['sonars'][0]['pose']['theta'] = 3.49
    data['kinematic'] = {'model': 'omni', 'parameters': {'a_uy_uy': 0.1}}
    data['sensors']['rfid_readers'] = [{'frame_id': 'tags'}]
    robot = parse_robot(data, 'robot.yaml')
    assert robot.points == ((-0.2, -0.1), (0.3, -0.1), (0.3, 0.1), (-0.2, 0.1))
    assert robot.radius == pytest.approx(math.hypot(0.3, 0.1))
    assert (robot.lasers[0].min_angle, robot.lasers[0].max_angle) == (0.0, 2 * math.pi)
    assert robot.sonars[0].pose[2] == pytest.approx(3.49 - 2 * math.pi)
    assert robot.kinematic.model == 'omni' and robot.kinematic.noisy
    assert robot.kinematic.parameters[4] == 0.1 and sum(robot.kinematic.parameters) == 0.1
    assert robot.unsimulated == ('rfid_reader tags',)
    assert parse_robot(edited((('kinematic',), None)), 'robot.yaml').kinematic == Kinematic()


def test_unreadable_robot_file_is_named(tmp_path):
    with pytest.raises(RobotFileError, match='missing.yaml: cannot read robot file'):
        load_robot(tmp_path / 'missing.yaml')
    broken = tmp_path / 'broken.yaml'
    broken.write_text('footprint: [\n')
    with pytest.raises(RobotFileError, match='broken.yaml:2: robot file is not valid YAML'):
        load_robot(broken)
