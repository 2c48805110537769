"""Running the installed executables as a user would."""

import os
from pathlib import Path
import signal
import subprocess
import sys

BIN = Path(sys.executable).parent


def executable(name):
    return str(BIN / name)


def start(name, *args, **popen_options):
    """Start an installed executable with its output captured as text."""
    return subprocess.Popen([executable(name), *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=dict(os.environ),
                            **popen_options)


def run(name, *args, stdin_text=None, timeout=60):
    return subprocess.run([executable(name), *args], input=stdin_text, capture_output=True,
                          text=True, timeout=timeout, env=dict(os.environ))


def interrupt(process, timeout=15):
    """Stop a process with Ctrl-C and return (exit code, stdout, stderr)."""
    process.send_signal(signal.SIGINT)
    stdout, stderr = process.communicate(timeout=timeout)
    return process.returncode, stdout, stderr
