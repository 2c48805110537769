"""stdr_ctl as a separate process against a running stdr_lite: answers and exit codes."""

import os
import re
import subprocess

from processes import executable, interrupt, run, start
import pytest

# Its tests share a module-scoped fixture: one worker runs them all (pytest.ini: loadgroup).
pytestmark = pytest.mark.xdist_group('stdr_ctl_simulator')

SIM_TIME = re.compile(r'sim time (\S+) s')


@pytest.fixture(scope='module')
def simulator():
    process = start('stdr_lite', '--ros-args', '-p', 'real_time_factor:=5.0')
    try:
        yield process
    finally:
        interrupt(process)


def ctl(*args, timeout=60, cwd=None):
    return run('stdr_ctl', *args, timeout=timeout, cwd=cwd)


def answer_of(*args):
    """Return what stdr_ctl printed, failing the test with its complaint unless it exited 0."""
    answer = ctl(*args)
    assert answer.returncode == 0, answer.stderr
    return answer.stdout.strip()


def sim_time(name='robot0'):
    return float(SIM_TIME.search(answer_of('get', name)).group(1))


def test_pause_step_and_play(simulator):
    assert answer_of('pause') == 'paused'
    assert answer_of('state') == 'paused'
    before = sim_time()
    assert answer_of('step', '25') == 'stepped 25'
    assert sim_time() == pytest.approx(before + 0.5)
    assert answer_of('simulate', '10') == 'simulated 10'
    assert sim_time() == pytest.approx(before + 0.7)
    assert answer_of('play') == 'playing'


def test_spawn_move_list_and_delete(simulator):
    assert answer_of('spawn', 'obstacle', '6', '6', '--name', 'rock') == 'spawned rock'
    assert answer_of('move', 'rock', '7', '6').startswith('rock at x 7.000')
    assert answer_of('list', '--category', 'static').startswith(
        'rock: x 7.000 y 6.000 theta 0.0000')
    assert 'static obstacle of radius 0.25 m' in answer_of('info', 'rock')
    assert answer_of('delete', 'rock') == 'deleted rock'
    assert 'rock' not in answer_of('list')


def test_a_robot_file_spawns_by_a_path_relative_to_stdr_ctl(simulator, tmp_path):
    (tmp_path / 'robots').mkdir()
    (tmp_path / 'robots' / 'scanner.xml').write_text(
        '<robot><robot_specifications><laser><filename>laser_sensors/lds_01.xml</filename>'
        '<laser_specifications><frame_id>scan</frame_id></laser_specifications></laser>'
        '</robot_specifications></robot>')
    answer = ctl('spawn', 'robots/scanner.xml', '5', '5', '--name', 'turtle', cwd=tmp_path)
    assert (answer.returncode, answer.stdout.strip()) == (0, 'spawned turtle'), answer.stderr
    info = answer_of('info', 'turtle')
    assert 'with scan, ' in info and '; topics under /turtle' in info
    # An STDR-layout file reads as under STDR: its noise is not applied, and info says so.
    assert "its file's sensor noise not applied, as STDR reads its layout" in info
    assert answer_of('delete', 'turtle') == 'deleted turtle'


def ours(stderr):
    """
    Return stderr without Fast DDS's shared-memory port errors.

    Under load Fast DDS may fail to lock a shared-memory port another participant is opening
    and says so on stderr (eProsima/Fast-DDS#6117, open); the participant goes on over UDP.
    That line is the middleware's, not stdr_ctl's answer.
    """
    return '\n'.join(line for line in stderr.splitlines() if 'RTPS_TRANSPORT_SHM' not in line)


def test_a_refusal_is_one_line_and_exit_code_1(simulator):
    answer = ctl('spawn', 'obstacle', '0.1', '0.1', '--name', 'stuck')
    assert answer.returncode == 1
    refusal = ours(answer.stderr)
    assert refusal.startswith('stdr_ctl: spawn refused: INVALID_POSE: ')
    assert len(refusal.splitlines()) == 1
    missing = ctl('delete', 'nobody')
    assert missing.returncode == 1 and 'RESULT_NOT_FOUND' in missing.stderr


def test_features_worlds_and_spawnables_are_listed(simulator):
    features = answer_of('features')
    assert 'step_simulation_action' in features and 'stdr_lite_obstacle_yaml' in features
    worlds = answer_of('worlds')
    assert worlds.startswith('factory: ') and '\nlab_room: ' in worlds
    assert answer_of('world').startswith('lab_room: ')
    assert 'moving_obstacle: moving obstacle' in answer_of('spawnables')


@pytest.mark.parametrize('args', [['step', 'many'], ['move', 'robot0', '1', 'nan'],
                                  ['reset', 'everything'], ['fly'], []])
def test_bad_arguments_exit_2_without_asking(args):
    answer = ctl(*args)
    assert answer.returncode == 2
    assert answer.stderr.startswith('stdr_ctl') and ': error: ' in answer.stderr
    assert len(answer.stderr.strip().splitlines()) == 1 and 'Traceback' not in answer.stderr


def test_no_simulator_answering_is_exit_code_1():
    answer = ctl('--simulator', '/nobody', '--timeout', '1', 'state')
    assert answer.returncode == 1
    assert 'no simulator answering: /nobody/get_simulation_state' in answer.stderr


@pytest.mark.parametrize('profile', ['ours', 'none'])
def test_fast_dds_speaks_on_stderr_leaving_stdout_to_the_answer(profile):
    """Fast DDS's errors (logged, or printed on std::cout) go to stderr, with a profile or none."""
    environment = dict(os.environ, ROS_DOMAIN_ID='240')  # Fast DDS refuses it, with errors
    if profile == 'none':
        environment.pop('FASTRTPS_DEFAULT_PROFILES_FILE')
    answer = subprocess.run([executable('stdr_ctl'), 'state'], capture_output=True, text=True,
                            timeout=60, env=environment)
    assert answer.returncode != 0
    assert 'RTPS' in answer.stderr and 'port number is too high' in answer.stderr
    assert 'RTPS' not in answer.stdout and 'port number' not in answer.stdout
