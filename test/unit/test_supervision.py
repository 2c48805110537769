"""Commands stopped whatever they do: ignore Ctrl-C, fork into a session of their own, flood."""

import signal
import sys

from lab_grader import supervision
from lab_grader.supervision import marked, Supervised
from processes import wait_until
import pytest


@pytest.fixture(autouse=True)
def short_graces(monkeypatch):
    monkeypatch.setattr(supervision, 'INTERRUPT_GRACE', 1.0)
    monkeypatch.setattr(supervision, 'TERMINATE_GRACE', 1.0)


def python(folder, code):
    """Start python -c code in folder, marked after it, once it has said it is ready."""
    folder.mkdir(exist_ok=True)
    command = Supervised([sys.executable, '-c', 'import os, signal, sys\n' + code],
                         str(folder), folder / 'output.txt')
    wait_until(lambda: 'ready' in command.last_lines, f'{folder.name} ready')
    return command


def test_ctrl_c_first(tmp_path):
    command = python(tmp_path, 'print("ready", flush=True)\nsignal.pause()')
    ended_by, seconds, leftovers = command.stop()
    assert (ended_by, leftovers) == ('SIGINT', []) and seconds < 1.0
    assert command.exit_code == -2 and not command.running
    assert any('KeyboardInterrupt' in line for line in command.last_lines)


def test_ctrl_c_reaches_a_command_whatever_the_grader_inherited(tmp_path):
    """A grader run as a script's background job ignores SIGINT; its commands must not."""
    ignored = signal.signal(signal.SIGINT, signal.SIG_IGN)
    blocked = signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGTERM])
    try:
        command = python(tmp_path, 'print("ready", flush=True)\nsignal.pause()')
    finally:
        signal.signal(signal.SIGINT, ignored)
        signal.pthread_sigmask(signal.SIG_SETMASK, blocked)
    assert command.stop()[0] == 'SIGINT' and command.exit_code == -2


def test_a_command_ignoring_ctrl_c_ends_by_sigterm_and_one_ignoring_both_by_sigkill(tmp_path):
    stubborn = python(tmp_path / 'a', 'signal.signal(signal.SIGINT, signal.SIG_IGN)\n'
                      'print("ready", flush=True)\nsignal.pause()')
    assert stubborn.stop()[0] == 'SIGTERM'
    deaf = python(tmp_path / 'b', 'signal.signal(signal.SIGINT, signal.SIG_IGN)\n'
                  'signal.signal(signal.SIGTERM, signal.SIG_IGN)\n'
                  'print("ready", flush=True)\nsignal.pause()')
    assert deaf.stop()[0] == 'SIGKILL' and deaf.exit_code == -9


def test_a_child_in_a_session_of_its_own_is_found_and_stopped(tmp_path):
    command = python(tmp_path, 'if os.fork() == 0:\n    os.setsid()\n    signal.pause()\n'
                     '    os._exit(0)\nprint("ready", flush=True)')
    wait_until(lambda: not command.running, 'the command ending by itself')
    assert command.exit_code == 0
    left = marked(command.marker)
    assert len(left) == 1 and left[0].pid != command.process.pid
    ended_by, _, leftovers = command.stop()
    assert ended_by == 'itself' and len(leftovers) == 1 and 'python' in leftovers[0]
    assert not marked(command.marker)


def test_output_is_kept_bounded_with_its_last_lines(tmp_path):
    command = python(tmp_path, 'for n in range(40000): print("x" * 60, n)\nprint("the end")\n'
                     'print("ready")')
    wait_until(lambda: not command.running, 'the command ending by itself')
    command.stop()
    output = (tmp_path / 'output.txt').read_bytes()
    assert len(output) < (1 << 20) + 100 and output.endswith(b'[output cut short at 1 MB]\n')
    assert list(command.last_lines)[-2:] == ['the end', 'ready'] and len(command.last_lines) == 40


def test_a_command_that_cannot_start_says_why(tmp_path):
    command = Supervised([str(tmp_path / 'missing')], 'm', tmp_path / 'output.txt')
    assert command.start_error.startswith('cannot start') and 'No such file' in (
        command.start_error)
    assert not command.running and command.stop() == ('itself', 0.0, [])
