"""stdr_lite and move_robot as installed executables, including the lab's own session."""

import re
import signal
import subprocess

from processes import executable, interrupt, run, start
import pytest

POSE_LINE = re.compile(r'Current position, x: (\S+), y: (\S+), theta: (\S+)')


@pytest.mark.parametrize('name', ['stdr_lite', 'move_robot', 'waypoint_controller',
                                  'course_monitor', 'stdr_viewer'])
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
    """
    Run the simulator at four times real time, to be quick.

    move_robot hands each move's duration to the simulator (pause, simulate_steps, play), so a
    loaded machine delays a move but never lengthens it.
    """
    process = start('stdr_lite', '--ros-args', '-p', 'real_time_factor:=4.0')
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
    assert straight == pytest.approx((6.0, 2.0, 0.0), abs=0.05)
    assert straight[2] == pytest.approx(0.0, abs=0.5)
    assert turned[:2] == pytest.approx(straight[:2], abs=0.005)
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
    # One step late would read 45.9 degrees.
    assert poses(session.stdout)[-1][2] == pytest.approx(45.0, abs=0.05)


def test_move_robot_times_by_odometry_without_the_stepping_api(simulator):
    session = run('move_robot', '--ros-args', '-p', 'simulator:=elsewhere',
                  stdin_text='0\n45\n1\n', timeout=60)
    assert session.returncode == 0, session.stderr
    assert 'moves are timed by the odometry' in session.stderr
    assert poses(session.stdout)[-1][2] == pytest.approx(45.0, abs=3.0)


def test_simulator_stops_on_ctrl_c_even_when_its_parent_ignored_it():
    process = subprocess.Popen([executable('stdr_lite')], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    try:
        process.stderr.readline()
    finally:
        code, _, stderr = interrupt(process)
    assert code == 0, stderr


@pytest.mark.parametrize('text, message', [
    ('1 2 3 4\n', 'course.txt:1: 4 numbers'),
    ('1 2 3\n4 5 six\n', "course.txt:2: 'six' is not a number"),
    ('', 'course.txt: no waypoints'),
])
def test_controller_refuses_a_bad_file_in_one_line(tmp_path, text, message):
    course = tmp_path / 'course.txt'
    course.write_text(text)
    result = run('waypoint_controller', str(course))
    assert result.returncode == 2
    assert message in result.stderr
    assert 'Traceback' not in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_controller_finishes_a_course_against_the_simulator_process(tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('2.5 2 0\n2.5 3 90\n')
    simulator = start('stdr_lite', '--ros-args', '-p', 'real_time_factor:=4.0')
    try:
        result = run('waypoint_controller', str(course), '--ros-args', '-p', 'use_sim_time:=true',
                     timeout=120)
    finally:
        interrupt(simulator)
    assert result.returncode == 0, result.stderr
    kinds = re.findall(r'\]: (STARTED|WAYPOINT \d|FINISHED)', result.stderr)
    assert kinds == ['STARTED', 'WAYPOINT 1', 'WAYPOINT 2', 'FINISHED']


def test_lockstep_runs_across_two_processes_are_identical(tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 45\n2 3 180\n2 3 -90\n')
    runs = []
    for _ in range(2):
        simulator = start('stdr_lite', '--ros-args', '-p', 'lockstep:=true', '-p',
                          'real_time_factor:=0.0')
        try:
            result = run('waypoint_controller', str(course), timeout=120)
        finally:
            interrupt(simulator)
        assert result.returncode == 0, result.stderr
        runs.append(re.findall(r'\]: ((?:STARTED|WAYPOINT|FINISHED).*)', result.stderr))
    assert runs[0][-1] == 'FINISHED' and len(runs[0]) == 5
    assert runs[0] == runs[1]
