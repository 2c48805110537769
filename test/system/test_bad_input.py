"""Bad input at start-up: one line naming it, exit code 2, no traceback, no hang."""

import json
import os
from pathlib import Path

from map_fixtures import png_header
from processes import run
import pytest


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
    (['-p', 'max_linear_speed:=.inf'], 'max_linear_speed must be in (0, 100], got inf'),
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
    record = tmp_path / 'run.jsonl'
    record.write_text(json.dumps({'course': 'c', 'waypoints': [[1, 2, 0]],
                                  'distance_tolerance': 0.1, 'angle_tolerance': 0.1}) + '\n')
    result = run('plot_run', str(record), '--map', str(files / 'bomb.yaml'))
    assert_one_line_refusal(result, 'bomb.png: map image is too large')


def test_plot_run_draws_an_interrupted_record_and_says_so(tmp_path):
    record = tmp_path / 'run.jsonl'
    header = {'course': 'c', 'waypoints': [[2, 2, 0]], 'distance_tolerance': 0.1,
              'angle_tolerance': 0.1}
    lines = [json.dumps(header)] + [json.dumps({'t': 0.02 * k, 'pose': [1 + 0.01 * k, 2, 0]})
                                    for k in range(50)]
    record.write_text('\n'.join(lines) + '\n{"t": 1.0, "pose": [1.5, 2.')
    result = run('plot_run', str(record))
    assert result.returncode == 0, result.stderr
    assert f'{record}:52: the last line was cut short' in result.stderr
    assert Path(tmp_path / 'run.png').stat().st_size > 10000
