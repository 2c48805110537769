"""Bad input at start-up: one line naming it, exit code 2, no traceback, no hang."""

import os
from pathlib import Path
import subprocess
import sys

from installed_executables import PARAMETER_TABLES
from map_fixtures import png_header
from processes import executable, run
import pytest
from run_bags import write_run


@pytest.fixture
def files(tmp_path):
    """Give bad input files by name."""
    (tmp_path / 'bomb.png').write_bytes(png_header(14000, 14000))
    (tmp_path / 'bomb.yaml').write_text('image: bomb.png\nresolution: 0.05\norigin: [0, 0, 0]\n')
    (tmp_path / 'names.yaml').write_text('robots:\n  - {name: robé}\n')
    (tmp_path / 'fast.yaml').write_text(
        'footprint: {radius: 0.2}\nsensors:\n  sonars:\n    - {frame_id: sonar_0, cone_angle: '
        '0.5, min_range: 0.1, max_range: 3, frequency: 1e12}\n')
    (tmp_path / 'passwd').write_text('root:x:0:0:root:/root:/bin/bash\n' * 20)
    os.mkfifo(tmp_path / 'fifo.txt')
    laser = ('footprint: {{radius: 0.2}}\nsensors:\n  lasers:\n    - {{frame_id: {}, '
             'min_angle: -1, max_angle: 1, min_range: 0.1, max_range: 4, num_rays: 5, '
             'frequency: 10}}\n')
    (tmp_path / 'long_names.yaml').write_text(f'robots:\n  - {{name: {"r" * 248}}}\n')
    (tmp_path / 'long_frame.yaml').write_text(laser.format('l' * 250))
    (tmp_path / 'odom_laser.yaml').write_text(laser.format('odom'))
    (tmp_path / 'nested.yaml').write_text('[' * 5000 + ']' * 5000 + '\n')
    (tmp_path / 'notyaml.yaml').write_text('a: [[[[\n')
    (tmp_path / 'nested_params.yaml').write_text(
        'stdr_lite:\n  ros__parameters:\n    initial_pose: ' + '[' * 5000 + ']' * 5000 + '\n')
    return tmp_path


def assert_one_line_refusal(result, message):
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert 'Traceback' not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr


@pytest.mark.parametrize('arguments, message', [
    (['-p', 'robot_name:=robé'], 'robot_name must be a ROS name'),
    (['-p', 'rate_hz:=.inf'], 'rate_hz must be in [1, 1000], got inf'),
    (['-p', 'rate_hz:=1e12'], 'rate_hz must be in [1, 1000], got 1e+12'),
    (['-p', 'max_linear_speed:=.inf'], 'max_linear_speed must be in [0, 10000], got inf'),
    (['-p', 'safety_angular_speed:=0.5'], 'safety_angular_speed must be in [1, 10000], got 0.5'),
    (['-p', 'robots_file:=FILES/names.yaml'], 'robots[0].name: expected a ROS name'),
    (['-p', 'robot_description:=FILES/fast.yaml'],
     'sensors.sonars[0].frequency: must be in [0.001, 1000], got 1e+12'),
    (['-p', 'map_yaml:=FILES/bomb.yaml'], 'bomb.png: map image is too large'),
    (['-p', 'robot_description:=FILES/passwd'], 'expected a mapping, got a text of'),
    (['-p', 'robot_description:=/dev/zero'], '/dev/zero: robot file is not a regular file'),
])
def test_the_simulator_refuses_bad_input_in_one_line(files, arguments, message):
    arguments = [argument.replace('FILES', str(files)) for argument in arguments]
    result = run('stdr_lite', '--ros-args', *arguments)
    assert_one_line_refusal(result, message)
    assert 'root:x' not in result.stderr


@pytest.mark.parametrize('arguments, message', [
    (['FILES/fifo.txt'], 'fifo.txt: waypoint file is not a regular file'),
    (['/dev/zero'], '/dev/zero: waypoint file is not a regular file'),
    (['FILES/passwd'], 'passwd:1: a text of 31 characters is not a number'),
    (['--ros-args', '-p', 'distance_tolerance:=.inf'],
     'distance_tolerance must be in (0, 10], got inf'),
    (['--ros-args', '-p', 'angle_tolerance_deg:=-5.0'],
     'angle_tolerance_deg must be in (0, 180], got -5'),
])
def test_the_controller_refuses_bad_input_in_one_line(files, arguments, message):
    arguments = [argument.replace('FILES', str(files)) for argument in arguments]
    assert_one_line_refusal(run('waypoint_controller', *arguments, timeout=30), message)


def test_plot_run_refuses_a_decompression_bomb_as_its_map(files, tmp_path):
    record = tmp_path / 'run.mcap'
    write_run(record).close()
    result = run('plot_run', str(record), '--map', str(files / 'bomb.yaml'))
    assert_one_line_refusal(result, 'bomb.png: map image is too large')


def test_plot_run_draws_an_interrupted_record_and_says_so(tmp_path):
    record = tmp_path / 'run.mcap'
    bag = write_run(record, steps=20_000, finish=False)
    bag._stream.flush()  # killed here: no summary, the last chunk unwritten
    result = run('plot_run', str(record))
    assert result.returncode == 0, result.stderr
    assert f'{record}: the bag was cut short' in result.stderr
    assert Path(tmp_path / 'run.png').stat().st_size > 10000


ROS_EXECUTABLES = {'stdr_lite': [], 'stdr_viewer': [], 'move_robot': [], 'stdr_ctl': ['state'],
                   'waypoint_controller': [], 'course_monitor': [], 'record_run': []}


@pytest.mark.parametrize('name', ROS_EXECUTABLES)
def test_malformed_ros_arguments_are_one_line_for_every_executable(name):
    result = run(name, *ROS_EXECUTABLES[name], '--ros-args', '-r', 'foo', timeout=30)
    assert_one_line_refusal(result, f"{name}: error: bad --ros-args: Couldn't parse remap rule: "
                            "'-r foo'")
    assert '.c:' not in result.stderr


@pytest.mark.parametrize('name', PARAMETER_TABLES)
def test_a_bad_parameter_is_refused_before_the_node_loads(name):
    """The line comes before rclpy, numpy and numba load (a second or two of CPU saved)."""
    result = subprocess.run(
        [sys.executable, '-X', 'importtime', executable(name), '--ros-args', '-p', 'no_such:=1'],
        capture_output=True, text=True, timeout=30, env=dict(os.environ))
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert lines[-1].startswith(f"{name}: error: unknown parameter 'no_such' for {name}")
    loaded = {line.rsplit('|', 1)[-1].strip() for line in lines[:-1]}
    assert not loaded & {'rclpy', 'numpy', 'numba'}, sorted(loaded & {'rclpy', 'numpy'})


@pytest.mark.parametrize('arguments, message', [
    (['-p'], "Couldn't parse trailing -p flag"),
    (['-p', 'rate_hz'], "Couldn't parse parameter override rule: '-p rate_hz'"),
    (['--params-file', '/no/such/params.yaml'], 'Error opening YAML file'),
    (['--params-file', 'FILES/notyaml.yaml'], "Couldn't parse params file"),
    (['--params-file', 'FILES/nested_params.yaml'], 'parameter initial_pose:'),
    (['-p', 'rate_hz:=50', '-p', 'rate_hz_:=3.0'],
     "unknown parameter 'rate_hz_' for stdr_lite; did you mean rate_hz?"),
    (['-p', 'robots_file:=FILES/long_names.yaml'], 'cmd_vel would be 257 characters long; ROS '
     'allows at most 247: shorten its name or namespace'),
    (['-p', 'robot_description:=FILES/long_frame.yaml'], 'shorten the sensor frame_id'),
    (['-p', 'robot_description:=FILES/odom_laser.yaml'], 'names one of the robot topics'),
    (['-p', 'odom_frame_id:=base_link'], 'odom_frame_id and base_frame_id are both'),
    (['-p', 'map_yaml:=FILES/nested.yaml'], 'nested'),
    (['-p', 'robot_description:=FILES/nested.yaml'], 'nested'),
    (['-p', 'robots_file:=FILES/nested.yaml'], 'nested'),
])
def test_the_simulator_refuses_what_it_cannot_be_in_one_line(files, arguments, message):
    arguments = [argument.replace('FILES', str(files)) for argument in arguments]
    assert_one_line_refusal(run('stdr_lite', '--ros-args', *arguments), message)


def test_the_controller_names_the_parameter_meant(files):
    result = run('waypoint_controller', '--ros-args', '-p', 'stall_timout:=5.0', timeout=30)
    assert_one_line_refusal(result, "unknown parameter 'stall_timout' for waypoint_controller; "
                            'did you mean stall_timeout?')


def test_whole_numbers_are_taken_for_doubles(tmp_path):
    result = run('stdr_lite', '--ros-args', '-p', 'rate_hz:=2000', timeout=30)
    assert_one_line_refusal(result, 'rate_hz must be in [1, 1000], got 2000')


@pytest.mark.parametrize('name, arguments', [
    ('stdr_viewer', ['--ros-args', '-p', 'robot_description:=FILES/nested.yaml']),
    ('plot_run', ['FILES/run.mcap', '--map', 'FILES/nested.yaml']),
])
def test_nested_yaml_is_one_line_for_the_viewer_and_plot_run(files, name, arguments):
    write_run(files / 'run.mcap').close()
    arguments = [argument.replace('FILES', str(files)) for argument in arguments]
    assert_one_line_refusal(run(name, *arguments, timeout=30), 'is nested')


@pytest.mark.parametrize('record', ['COURSE', 'FILES/fifo.txt', '/dev/null', 'FILES'])
def test_course_monitor_writes_over_nothing(files, record):
    course = files / 'course.txt'
    course.write_text('3 2 0\n')
    record = {'COURSE': str(course)}.get(record, record.replace('FILES', str(files)))
    result = run('course_monitor', str(course), '--ros-args', '-p', f'bag:={record}',
                 timeout=30)
    assert_one_line_refusal(result, f'bag {record}: ')
    assert course.read_text() == '3 2 0\n'


@pytest.mark.parametrize('name, arguments, message', [
    ('stdr_lite', ['surplus'], 'stdr_lite: error: unrecognized arguments: surplus'),
    ('plot_run', [], 'plot_run: error: the following arguments are required: record'),
    ('stdr_ctl', ['step', 'many'], 'stdr_ctl step: error: argument steps: not a whole number'),
    ('waypoint_controller', ['a.txt', 'b.txt'], 'unrecognized arguments: b.txt'),
])
def test_bad_command_lines_are_one_line(name, arguments, message):
    assert_one_line_refusal(run(name, *arguments, timeout=30), message)
