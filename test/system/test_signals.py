"""Ctrl-C and SIGTERM end every executable within a second, in every mode, exit 0, quietly."""

import os
from pathlib import Path
import signal
import subprocess
import time

from bench.realtime import write_robot_grid
import numpy as np
from PIL import Image
from processes import run, start, start_logged, stop, wait_for_text
import pytest

STOP_WITHIN = 1.0
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


@pytest.mark.parametrize('signal_number', SIGNALS, ids=lambda number: number.name)
@pytest.mark.parametrize('mode', MODES)
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
    log = tmp_path / f'{name}.log'
    process = start_logged(name, log=log, stdin=subprocess.PIPE, cwd=tmp_path)
    time.sleep(0.3)
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


@pytest.mark.parametrize('signal_number', SIGNALS, ids=lambda number: number.name)
@pytest.mark.parametrize('request_', ['step', 'load-world'])
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
