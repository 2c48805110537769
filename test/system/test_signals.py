"""Ctrl-C and SIGTERM end every executable promptly, in every mode, exit 0, quietly."""

import os
from pathlib import Path
import signal
import subprocess
import time

from bench.realtime import write_robot_grid
import numpy as np
from PIL import Image
from processes import (executable, run, signals_held, start, start_logged, stop, wait_for_text,
                       wait_until)
import pytest

# Within a second on a quiet machine; beside two busy loops and the suite's other workers ends
# took up to 3.28 s (doc/robustness.md says so): the suite checks what holds there.
STOP_WITHIN = 4.0
SIGNALS = [signal.SIGINT, signal.SIGTERM]


MODES = {
    'free-running unpaced': lambda folder: ['-p', 'real_time_factor:=0.0'],
    'lockstep': lambda folder: ['-p', 'lockstep:=true'],
    'behind real time': lambda folder: ['-p', f'robots_file:={write_robot_grid(folder, 200)}',
                                        '-p', 'rate_hz:=1000.0'],
    '1000 robots': lambda folder: ['-p', f'robots_file:={write_robot_grid(folder, 1000)}'],
}


def assert_quiet_prompt_exit(process, signal_number, log):
    code, seconds = stop(process, signal_number)
    output = Path(log).read_text()
    assert code == 0, output
    assert seconds < STOP_WITHIN, f'took {seconds:.2f} s'
    assert 'Traceback' not in output and 'KeyboardInterrupt' not in output


# Both signals take the one path of the node runtime: at 1000 robots (the teardown at size,
# 20 s a run) one of them is enough.
MODE_SIGNALS = [(mode, number) for mode in MODES for number in SIGNALS
                if not (mode == '1000 robots' and number == signal.SIGINT)]


@pytest.mark.parametrize('mode, signal_number', MODE_SIGNALS,
                         ids=[f'{mode}-{number.name}' for mode, number in MODE_SIGNALS])
def test_the_simulator_stops_in_every_mode(tmp_path, mode, signal_number):
    log = tmp_path / 'stdr_lite.log'
    process = start_logged('stdr_lite', '--ros-args', *MODES[mode](tmp_path), log=log)
    try:
        wait_for_text(log, 'real_time_factor', process, timeout=60.0)
        if mode in ('behind real time', '1000 robots'):
            wait_for_text(log, 'behind real_time_factor', process)
        time.sleep(0.5)
    finally:
        assert_quiet_prompt_exit(process, signal_number, log)


@pytest.mark.parametrize('signal_number', SIGNALS, ids=lambda number: number.name)
@pytest.mark.parametrize('name', ['stdr_lite', 'waypoint_controller', 'course_monitor',
                                  'record_run', 'move_robot', 'stdr_viewer', 'plot_run'])
def test_a_signal_while_starting_up_is_quiet(tmp_path, name, signal_number):
    """From the package's first line on, while the modules load (a busy machine: seconds)."""
    log = tmp_path / f'{name}.log'
    process = start_logged(name, log=log, stdin=subprocess.PIPE, cwd=tmp_path)
    wait_until(lambda: signals_held(process), 'the signals held by the package', process)
    assert_quiet_prompt_exit(process, signal_number, log)


@pytest.mark.parametrize('signal_number', SIGNALS, ids=lambda number: number.name)
@pytest.mark.parametrize('name, ready', [
    ('waypoint_controller', 'following'), ('course_monitor', ''), ('move_robot', ''),
    ('stdr_viewer', '')])
def test_a_waiting_node_stops_on_a_signal(tmp_path, name, ready, signal_number):
    os.environ.setdefault('SDL_VIDEODRIVER', 'dummy')
    log = tmp_path / f'{name}.log'
    process = start_logged(name, log=log, stdin=subprocess.PIPE)
    try:
        if ready:
            wait_for_text(log, ready, process)
        time.sleep(2.0)
    finally:
        assert_quiet_prompt_exit(process, signal_number, log)


@pytest.fixture
def big_world(tmp_path):
    """Write a map of 4096 x 4096 cells, the largest a world may be."""
    pixels = np.full((4096, 4096), 254, dtype=np.uint8)
    pixels[::64, :] = pixels[:, ::64] = 0
    Image.fromarray(pixels).save(tmp_path / 'big.pgm')
    (tmp_path / 'big.yaml').write_text('image: big.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n')
    return tmp_path / 'big.yaml'


@pytest.mark.parametrize('request_, signal_number', [('step', signal.SIGINT),
                                                     ('load-world', signal.SIGTERM)],
                         ids=['step-SIGINT', 'load-world-SIGTERM'])
def test_the_simulator_stops_during_a_long_request(tmp_path, big_world, request_,
                                                   signal_number):
    log = tmp_path / 'stdr_lite.log'
    robots = write_robot_grid(tmp_path, 200)
    process = start_logged('stdr_lite', '--ros-args', '-p', f'robots_file:={robots}', log=log)
    client = None
    try:
        wait_for_text(log, 'real_time_factor', process, timeout=60.0)
        assert run('stdr_ctl', 'pause').returncode == 0
        arguments = ['step', '10000'] if request_ == 'step' else ['load-world', str(big_world)]
        client = start('stdr_ctl', *arguments)
        time.sleep(1.5)
        assert client.poll() is None, 'the request was over before the signal'
    finally:
        assert_quiet_prompt_exit(process, signal_number, log)
        if client is not None:
            client.kill()
            client.wait()


# A signal this early lands in the interpreter's own start (10 to 50 ms before the package's
# first line runs, from its .pth file) or while the package holds it (early_signals.py).
FIRST_MOMENTS = (0.0, 0.01, 0.02, 0.05, 0.1)
WAITING_ARGUMENTS = {
    'stdr_lite': [], 'stdr_viewer': [], 'move_robot': [], 'stdr_ctl': ['state'],
    'waypoint_controller': ['WAYPOINTS'], 'course_monitor': ['WAYPOINTS'], 'record_run': [],
    'plot_run': ['missing.mcap'], 'grade_lab': ['--courses', 'WAYPOINTS', '--', 'true']}


OURS = ('simple_robot_control', 'stdr_lite', 'waypoint_lab', 'waypoint_controller',
        'lab_grader')


def ended_before_its_first_line(code, signal_number, output):
    """Whether the signal ended Python's own start, as it ends any Python program's."""
    ours = OURS
    python_said = 'KeyboardInterrupt' in output or 'Fatal Python error' in output
    return (code == -signal_number and not output) or (
        code == 1 and signal_number == signal.SIGINT and python_said
        and not any(f'/{package}/' in output for package in ours))


def swallowed_by_the_interpreter(signal_number, output):
    """
    Whether Python's own start dropped the Ctrl-C, before any line of ours could hold it.

    Its default handler raised KeyboardInterrupt inside one of its import machinery's callbacks,
    where an exception is printed and dropped ("Exception ignored in"); the program then starts
    as if no signal had come. The one case out of our reach (doc/robustness.md).
    """
    return (signal_number == signal.SIGINT and output.startswith('Exception ignored in')
            and 'KeyboardInterrupt' in output and not any(f'/{package}/' in output
                                                          for package in OURS))


@pytest.mark.parametrize('moment', [0.3, 1.0])
def test_ctrl_c_ends_a_background_job_of_a_script_while_it_starts(tmp_path, moment):
    """
    A script's `prog &` starts prog with SIGINT ignored; its `kill -INT` must still end it.

    Held (blocked) from the package's first line, a signal is kept pending even while ignored
    (Linux drops an ignored signal only when it is not blocked), until the handlers take it.
    Before that first line, in Python's own start, an ignored SIGINT is lost: scripts stop
    what they start with SIGTERM (scripts/swarm.sh).
    """
    process = subprocess.Popen([executable('stdr_lite')], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, cwd=tmp_path,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    started = time.monotonic()
    while time.monotonic() - started < moment:
        pass  # the moment to send the signal at, not a wait for anything
    process.send_signal(signal.SIGINT)
    try:
        output, _ = process.communicate(timeout=10.0)
    except subprocess.TimeoutExpired:
        process.kill()
        pytest.fail(f'SIGINT at {moment:g} s was lost: still running 10 s later: '
                    f'{process.communicate()[0][-300:]}')
    assert process.returncode == 0, output


@pytest.mark.parametrize('name', WAITING_ARGUMENTS)
def test_a_signal_from_the_first_instant_ends_the_program(tmp_path, name):
    (tmp_path / 'waypoints.txt').write_text('3 2 0\n')
    arguments = [str(tmp_path / 'waypoints.txt') if argument == 'WAYPOINTS' else argument
                 for argument in WAITING_ARGUMENTS[name]]
    # Started as from a shell: the PyPI ROS wheels re-execute the interpreter once.
    environment = {key: value for key, value in os.environ.items()
                   if key != '_ROS_WHEELS_BOOTSTRAP_COMPLETE'}
    environment['SDL_VIDEODRIVER'] = 'dummy'
    outcomes = []
    for signal_number in SIGNALS:
        for moment in FIRST_MOMENTS:
            process = subprocess.Popen([executable(name), *arguments], stdin=subprocess.PIPE,
                                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                       text=True, env=environment, cwd=tmp_path)
            started = time.monotonic()
            while time.monotonic() - started < moment:
                pass  # the moment to send the signal at, not a wait for anything
            sent = time.monotonic()
            process.send_signal(signal_number)
            try:
                output, _ = process.communicate(timeout=10.0)
            except subprocess.TimeoutExpired:
                process.kill()
                output, _ = process.communicate()
                if swallowed_by_the_interpreter(signal_number, output):
                    outcomes.append(f'{signal_number.name} at {moment * 1000:.0f} ms: '
                                    "swallowed by Python's own start")
                    continue
                pytest.fail(f'{signal_number.name} at {moment * 1000:.0f} ms: still running '
                            f'10 s later: {output[-500:]}')
            took = time.monotonic() - sent
            what = f'{signal_number.name} at {moment * 1000:.0f} ms: {process.returncode}'
            outcomes.append(what)
            assert took < STOP_WITHIN, f'{what} took {took:.2f} s'
            assert (process.returncode == 0 and not output) or ended_before_its_first_line(
                process.returncode, signal_number, output), f'{what}: {output[-500:]}'
    print(f'{name}: {", ".join(outcomes)}')
