"""stdr_lite and move_robot as installed executables, including the lab's own session."""

import re

from processes import interrupt, run, start
import pytest

POSE_LINE = re.compile(r'Current position, x: (\S+), y: (\S+), theta: (\S+)')


@pytest.mark.parametrize('name', ['stdr_lite', 'move_robot'])
def test_help_lists_the_ros_parameters(name):
    result = run(name, '--help')
    assert result.returncode == 0
    assert f'usage: {name}' in result.stdout
    assert 'ROS parameters' in result.stdout


@pytest.mark.parametrize('args, message', [
    (['-p', 'map_yaml:=/no/such/map.yaml'], '/no/such/map.yaml: cannot read map file'),
    (['-p', 'initial_pose:=[0.1, 5.0, 0.0]'], 'touches a wall'),
])
def test_simulator_refuses_bad_configuration_in_one_line(args, message):
    result = run('stdr_lite', '--ros-args', *args)
    assert result.returncode == 2
    assert message in result.stderr
    assert 'Traceback' not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_move_robot_without_a_simulator_says_so():
    result = run('move_robot', '--ros-args', '-p', 'odom_timeout:=1.0', '-p',
                 'robot_name:=nobody', stdin_text='1\n0\n1\n')
    assert result.returncode == 1
    assert 'no odometry on /nobody/odom' in result.stderr
    assert 'Traceback' not in result.stderr


@pytest.fixture
def simulator():
    process = start('stdr_lite')
    try:
        yield process
    finally:
        if process.poll() is None:
            code, _, stderr = interrupt(process)
            assert code == 0, stderr
            assert 'Traceback' not in stderr


def poses(stdout):
    return [tuple(float(value) for value in match) for match in POSE_LINE.findall(stdout)]


def test_lab_transcript_is_reproduced(simulator):
    session = run('move_robot', stdin_text='1\n0\n5\n0\n10\n9\n1\n10\n9\n', timeout=120)
    assert session.returncode == 0, session.stderr
    start_pose, straight, turned, against_wall = poses(session.stdout)
    assert start_pose == (1.0, 2.0, 0.0)
    assert straight == pytest.approx((6.0, 2.0, 0.0), abs=0.02)
    assert straight[2] == pytest.approx(0.0, abs=0.5)
    assert turned[:2] == pytest.approx((6.0, 2.0), abs=0.005)
    assert turned[2] == pytest.approx(90.0, abs=0.5)
    assert against_wall[0] == pytest.approx(0.57, abs=0.06)
    assert against_wall[1] == pytest.approx(7.72, abs=0.08)
    assert against_wall[2] == pytest.approx(177.0, abs=2.0)


def test_move_robot_re_asks_after_a_bad_number(simulator):
    session = run('move_robot', stdin_text='fast\n0\nnan\n45\n-2\n1\n', timeout=60)
    assert session.returncode == 0, session.stderr
    assert "Not a finite number: 'fast'" in session.stdout
    assert "Not a finite number: 'nan'" in session.stdout
    assert 'Must be at least 0' in session.stdout
    assert poses(session.stdout)[-1][2] == pytest.approx(45.0, abs=0.5)
