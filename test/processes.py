"""Running the installed executables as a user would, wherever they were installed."""

import os
from pathlib import Path
import signal
import subprocess
import time

from simple_robot_control.share import installed_executable


def executable(name):
    """Return where an executable is installed (see share.installed_executable)."""
    return installed_executable(name)


def start(name, *args, **popen_options):
    """Start an installed executable with its output captured as text."""
    return subprocess.Popen([executable(name), *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=dict(os.environ),
                            **popen_options)


def run(name, *args, stdin_text=None, timeout=60, cwd=None, **popen_options):
    return subprocess.run([executable(name), *args], input=stdin_text, capture_output=True,
                          text=True, timeout=timeout, env=dict(os.environ), cwd=cwd,
                          **popen_options)


def interrupt(process, timeout=15, signal_number=signal.SIGINT):
    """Stop a process with Ctrl-C (or another signal); return (exit code, stdout, stderr)."""
    process.send_signal(signal_number)
    stdout, stderr = process.communicate(timeout=timeout)
    return process.returncode, stdout, stderr


def start_logged(name, *args, log, **popen_options):
    """Start an installed executable writing stdout and stderr to the file log."""
    with open(log, 'w') as stream:
        return subprocess.Popen([executable(name), *args], stdout=stream,
                                stderr=subprocess.STDOUT, text=True, env=dict(os.environ),
                                **popen_options)


def wait_until(condition, what, process=None, timeout=20.0):
    """Poll condition() until true; fail if process ends first or time runs out."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert process is None or process.poll() is None, (
            f'{process.args[0]} ended ({process.returncode}) before {what}')
        assert time.monotonic() < deadline, f'no {what} within {timeout} s'
        time.sleep(0.05)


def wait_for_text(log, text, process=None, timeout=20.0):
    """Wait until the file log holds text; fail if process ends first or time runs out."""
    def said():
        return text in Path(log).read_text()
    try:
        wait_until(said, f'saying {text!r}', process, timeout)
    except AssertionError as error:
        raise AssertionError(f'{error}; the log:\n{Path(log).read_text()}') from None
    return Path(log).read_text()


def stop(process, signal_number, timeout=10.0):
    """Send a signal and return (exit code, seconds until the process ended)."""
    sent = time.monotonic()
    process.send_signal(signal_number)
    process.wait(timeout=timeout)
    return process.returncode, time.monotonic() - sent


def signals_held(process) -> bool:
    """
    Whether Ctrl-C and SIGTERM are in the package's hands in process (Linux's /proc says).

    They are from the moment its .pth blocks them (early_signals.py) until its own handlers
    take them; before that, in the interpreter's first lines, nothing of the package runs yet
    and Python's own default ends the process. A process that has ended holds them too: its
    test goes on and sees how it ended.
    """
    try:
        status = Path(f'/proc/{process.pid}/status').read_text()
    except OSError:
        return True
    masks = dict(line.split(':\t', 1) for line in status.splitlines() if ':\t' in line)
    both = (1 << (signal.SIGINT - 1)) | (1 << (signal.SIGTERM - 1))
    return (int(masks['SigBlk'], 16) & both == both
            or int(masks['SigCgt'], 16) & (1 << (signal.SIGTERM - 1)) != 0)
