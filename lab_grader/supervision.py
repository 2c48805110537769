"""
Processes the grader starts, stopped whatever they do: hang, ignore Ctrl-C, fork, exit early.

Each command runs in a session and process group of its own, with a marker in its environment
that its children inherit. Stopping sends SIGINT (what Ctrl-C and ros2 launch send) to every
process carrying the marker, then SIGTERM, then SIGKILL, so a child that left the group
(setsid, a daemon) is found and stopped too. The grader is its children's subreaper, so
orphans come back to it to be reaped rather than to init. Each starts with SIGINT and SIGTERM
at their defaults and nothing blocked, whatever the grader inherited (a background job of a
script ignores SIGINT, and would pass that on): Ctrl-C reaches a submission as it would from a
terminal. Output is kept, bounded. No ROS here.
"""

from collections import deque
from collections.abc import Callable
import ctypes
import os
import signal
import subprocess
import threading
import time

import psutil

MARKER = 'GRADE_LAB_PROCESS'
MAX_OUTPUT_BYTES = 1 << 20
KEPT_LINES = 40
# Ctrl-C first, as ros2 launch does (it also waits 5 s before SIGTERM), then SIGTERM, then KILL.
INTERRUPT_GRACE = 5.0
TERMINATE_GRACE = 2.0
_PR_SET_CHILD_SUBREAPER = 36
# The pids of the commands' own processes, whose exit status their Popen collects.
_MANAGED = set()
_LOCK = threading.Lock()


def _default_signals():
    """In the child, just before exec: SIGINT and SIGTERM at their defaults, none blocked."""
    for number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(number, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_SETMASK, [])


def become_subreaper() -> None:
    """Have orphaned descendants of this process come back to it (Linux; ignored elsewhere)."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    except (OSError, AttributeError):
        pass


def marked(marker: str) -> list[psutil.Process]:
    """Return the running processes whose environment carries marker."""
    found = []
    for process in psutil.process_iter():
        try:
            if (process.environ().get(MARKER) == marker
                    and process.status() != psutil.STATUS_ZOMBIE):
                found.append(process)
        except (psutil.Error, OSError):
            continue
    return found


def describe(process: psutil.Process) -> str:
    """Name a process: its pid and command line, cut short."""
    try:
        # One line, whatever the arguments hold (python -c code has newlines).
        command = ' '.join(' '.join(process.cmdline()).split()) or process.name()
    except psutil.Error:
        command = '?'
    return f'pid {process.pid} ({command[:80]})'


def reap_orphans() -> None:
    """
    Collect the exit status of adopted orphans that have ended, so none stays a zombie.

    The commands' own processes are left to their Popen, which must see their exit status.
    """
    with _LOCK:
        managed = set(_MANAGED)
    for child in psutil.Process().children():
        try:
            if child.pid not in managed and child.status() == psutil.STATUS_ZOMBIE:
                os.waitpid(child.pid, os.WNOHANG)
        except (psutil.Error, ChildProcessError):
            continue


def stop_marked(marker: str) -> str:
    """Stop every process carrying marker; return the strongest signal it took (stop_all)."""
    return stop_all(lambda: marked(marker))


def stop_all(find: Callable[[], list[psutil.Process]]) -> str:
    """
    Stop every process find() gives: SIGINT, SIGTERM after INTERRUPT_GRACE, then SIGKILL.

    find() is asked again at each signal, so that a process started meanwhile goes too.
    Return the strongest signal it took ('' when none was running).
    """
    needed = ''
    for number, grace in ((signal.SIGINT, INTERRUPT_GRACE), (signal.SIGTERM, TERMINATE_GRACE),
                          (signal.SIGKILL, TERMINATE_GRACE)):
        running = find()
        if not running:
            break
        needed = number.name
        for process in running:
            try:
                process.send_signal(number)
            except psutil.Error:
                continue
        deadline = time.monotonic() + grace
        while running and time.monotonic() < deadline:
            time.sleep(0.05)
            running = [process for process in find() if _running(process)]
    reap_orphans()
    return needed


def _running(process):
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.Error:
        return False


class Supervised:
    """
    A command in a process group of its own, marked, its output kept in a file (bounded).

    start_error says why the command could not start ('' when it did).
    """

    def __init__(self, command, marker, output_path, cwd=None, env=None, pass_fds=()):
        self.marker = marker
        self.start_error = ''
        self.last_lines = deque(maxlen=KEPT_LINES)
        self.started_at = time.monotonic()
        self.ended_at = None
        self._output = open(output_path, 'wb', buffering=0)
        environment = dict(os.environ if env is None else env, **{MARKER: marker})
        try:
            self.process = subprocess.Popen(
                command, cwd=cwd, env=environment, stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True,
                preexec_fn=_default_signals, pass_fds=pass_fds)
        except OSError as error:
            self.process = None
            self.start_error = f'cannot start {command[0]}: {error.strerror}'
            self._output.close()
            return
        with _LOCK:
            _MANAGED.add(self.process.pid)
        self._reader = threading.Thread(target=self._read, name=f'output of {command[0]}',
                                        daemon=True)
        self._reader.start()

    @property
    def pid(self) -> int:
        return 0 if self.process is None else self.process.pid

    @property
    def running(self) -> bool:
        """Whether the command's own process still runs (its children aside)."""
        return not self._ended()

    def _ended(self):
        """Tell whether the command's own process has ended, noting when it was first seen so."""
        if self.process is not None and self.process.poll() is None:
            return False
        if self.ended_at is None:
            self.ended_at = time.monotonic()
        return True

    @property
    def seconds(self) -> float:
        """Return how long the command ran, or has run so far."""
        return (self.ended_at or time.monotonic()) - self.started_at

    @property
    def exit_code(self) -> int | None:
        return None if self.process is None else self.process.returncode

    def stop(self) -> tuple[str, float, list[str]]:
        """
        Stop the command and everything it started.

        Return (what ended it: 'itself' or the strongest signal it took, the seconds that took,
        the processes of it still running after it had ended by itself, stopped now).
        """
        if self.process is None:
            return 'itself', 0.0, []
        ended_before = not self.running
        leftovers = [describe(process) for process in marked(self.marker)] if ended_before \
            else []
        began = time.monotonic()
        needed = stop_marked(self.marker)
        self.process.wait()
        self._forget()
        self._ended()
        self._reader.join(timeout=TERMINATE_GRACE)
        ended_by = 'itself' if ended_before or not needed else needed
        return ended_by, time.monotonic() - began, leftovers

    def _forget(self):
        """Leave the command's process, now collected, to reap_orphans' care no more."""
        with _LOCK:
            _MANAGED.discard(self.process.pid)

    def _read(self):
        """
        Copy the output to the file, at most MAX_OUTPUT_BYTES of it, keeping its last lines.

        A file the disk refuses (full) is written no further; the output is read to its end.
        """
        pending, written = b'', 0
        with self._output:
            for chunk in iter(lambda: self.process.stdout.read1(65536), b''):
                if written < MAX_OUTPUT_BYTES:
                    part = chunk[:MAX_OUTPUT_BYTES - written]
                    written += len(part)
                    try:
                        self._output.write(part)
                        if written >= MAX_OUTPUT_BYTES:
                            self._output.write(b'\n[output cut short at 1 MB]\n')
                        self._output.flush()
                    except OSError:
                        written = MAX_OUTPUT_BYTES
                *lines, pending = (pending + chunk).split(b'\n')
                self.last_lines.extend(line.decode(errors='replace')[:300] for line in lines)
                pending = pending[-4096:]
        if pending:
            self.last_lines.append(pending.decode(errors='replace')[:300])
