"""
A submission's command, run under its course's reaper (reaper.py), and ended whole. No ROS here.

The reaper is the submission's parent and the subreaper of everything it starts, so the
submission's processes are the reaper's descendants, however they detach; the environment
marker of supervision.py is kept too, for the processes that leave both (none can, short of
another user's or the system's help). Stopping sends SIGINT to all of them, then SIGTERM,
then SIGKILL; a process that left the command's own tree (a daemon) is named, as is any still
running after the command ended by itself.
"""

import os
from pathlib import Path
import signal
import subprocess
import sys
import time

from lab_grader.sandbox import jail_descriptor, processes_of
from lab_grader.supervision import (describe, marked, reap_orphans, stop_all, Supervised,
                                    TERMINATE_GRACE)
import psutil

REAPER = str(Path(__file__).with_name('reaper.py'))
PROBE_TIMEOUT = 60.0
# A sandbox's /tmp with less than this free is full: what the submission wrote filled it.
FULL_BELOW = 64 << 10


class Submission(Supervised):
    """The submission's command under a reaper; its exit status comes from the reaper."""

    def __init__(self, command, marker, output_path, cwd=None, env=None, memory_mb=0,
                 jail=None):
        self._status_read, status_write = os.pipe()
        os.set_blocking(self._status_read, False)
        self._status_text = ''
        self._exit_code = self._main = None
        self.uid = jail['uid'] if jail else None
        self._in_namespaces = bool(jail)
        jail_fd = jail_descriptor(jail) if jail else -1
        descriptors = (status_write,) + ((jail_fd,) if jail else ())
        # Isolated (-I): the standard library alone, nothing from the submission's folder.
        reaper = [sys.executable, '-I', REAPER, str(status_write), str(memory_mb),
                  str(os.getpid()), str(jail_fd), '--', *command]
        try:
            super().__init__(reaper, marker, output_path, cwd, env, pass_fds=descriptors)
        finally:
            for descriptor in descriptors:
                os.close(descriptor)
        self.command = list(command)
        if self.process is None:
            self.start_error = self.start_error.replace(reaper[0], command[0], 1)

    def _poll_status(self):
        """Read what the reaper said of the command: `started`, `exit N`, `cannot start ...`."""
        chunk = b''
        if self._status_read is not None:
            try:
                chunk = os.read(self._status_read, 4096)
            except OSError:
                pass
        if chunk:
            self._status_text += chunk.decode(errors='replace')
            for line in self._status_text.splitlines():
                if line.startswith('cannot start '):
                    self.start_error = self.start_error or line
                elif line.startswith('started '):
                    self._main = self._host_pid(int(line.split()[1]))
                elif line.startswith('exit ') and self._exit_code is None:
                    self._exit_code = int(line.split()[1])
        elif self._exit_code is None and self.process.poll() is not None:
            # The reaper is gone (killed) without a word: the command's fate is unknown.
            self._exit_code = -signal.SIGKILL

    def _ended(self):
        if self.process is not None:
            self._poll_status()
            if self._exit_code is None:
                return False
        if self.ended_at is None:
            self.ended_at = time.monotonic()
        return True

    @property
    def exit_code(self) -> int | None:
        return self._exit_code

    def _host_pid(self, pid):
        """Return the pid this process knows a pid of the submission by (in its namespace)."""
        if not self._in_namespaces:
            return pid
        for process in _descendants(psutil.Process(self.process.pid)):
            try:
                with open(f'/proc/{process.pid}/status') as status:
                    for line in status:
                        if line.startswith('NSpid:'):
                            numbers = line.split()[1:]
                            if len(numbers) > 1 and int(numbers[-1]) == pid:
                                return process.pid
            except (OSError, ValueError):
                continue
        return None

    def _tree(self):
        """
        Return every running process of the submission: the reaper's descendants, marked.

        Under a uid of its own, every process of that uid is the submission's too, wherever
        it went.
        """
        found = {}
        try:
            for process in psutil.Process(self.process.pid).children(recursive=True):
                found[process.pid] = process
        except psutil.Error:
            pass
        for process in marked(self.marker) if self.uid is None else processes_of(self.uid):
            found[process.pid] = process
        for reaper in {self.process.pid} | self._namespaces_first():
            found.pop(reaper, None)
        return [process for process in found.values() if _alive(process)]

    def _namespaces_first(self):
        """Return the pid of the first process of the submission's namespaces (a reaper) if any."""
        if not self._in_namespaces:
            return set()
        try:
            return {child.pid for child in psutil.Process(self.process.pid).children()}
        except psutil.Error:
            return set()

    def disk_full(self) -> bool:
        """Whether the submission has filled its own /tmp (with namespaces; False otherwise)."""
        for first in self._namespaces_first():
            try:
                space = os.statvfs(f'/proc/{first}/root/tmp')
            except OSError:
                continue
            return space.f_bavail * space.f_frsize < FULL_BELOW
        return False

    def _detached(self):
        """Return the processes that left the command's own tree (adopted by the reaper)."""
        own = {self._main}
        try:
            own |= {process.pid for process in psutil.Process(self._main).children(
                recursive=True)}
        except (psutil.Error, TypeError, ValueError):
            pass
        return [process for process in self._tree() if process.pid not in own]

    def pids(self) -> set[int]:
        return {process.pid for process in self._tree()}

    def stop(self) -> tuple[str, float, list[str]]:
        """
        Stop the submission and every process it started.

        Return (what ended it: 'itself' or the strongest signal it took, the seconds that took,
        the processes it left: running after it had ended by itself, or detached from it).
        """
        if self.process is None:
            return 'itself', 0.0, []
        ended_before = not self.running
        leftovers = self._tree() if ended_before else self._detached()
        named = [describe(process) for process in leftovers]
        began = time.monotonic()
        needed = stop_all(self._tree)
        self._finish_reaper()
        ended_by = 'itself' if ended_before or not needed else needed
        return ended_by, time.monotonic() - began, named

    def _finish_reaper(self):
        """End the reaper, once it has said how the command ended, and collect it."""
        deadline = time.monotonic() + TERMINATE_GRACE
        while self._main is not None and not self._ended() and time.monotonic() < deadline:
            time.sleep(0.02)
        self.process.terminate()
        try:
            self.process.wait(timeout=TERMINATE_GRACE)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        if not self._ended():
            self._exit_code = -signal.SIGKILL
            self._ended()
        self._forget()
        os.close(self._status_read)
        self._status_read = None
        reap_orphans()
        self._reader.join(timeout=TERMINATE_GRACE)


def _alive(process):
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.Error:
        return False


def _descendants(process):
    try:
        return process.children(recursive=True)
    except psutil.Error:
        return []


def sandbox_problem(jail: dict, env: dict, output_path: Path) -> str:
    """
    Say why a submission could not run this package's Python in its sandbox ('' if it can).

    The uid of its own must read the interpreter and the installed package (a venv whose base
    interpreter lives in root's home is readable only with namespaces, which expose it).
    """
    probe = Submission([sys.executable, '-c', 'import rclpy, simple_robot_control'],
                       'grade_lab-probe', output_path, cwd=jail['cwd'], env=env, jail=jail)
    deadline = time.monotonic() + PROBE_TIMEOUT
    while probe.running and time.monotonic() < deadline:
        time.sleep(0.02)
    probe.stop()
    if probe.start_error:
        return probe.start_error
    if probe.exit_code != 0:
        said = ' | '.join(line for line in probe.last_lines if line.strip())[-300:]
        return (f'uid {jail["uid"]} cannot run {sys.executable} with this package '
                f'(exit code {probe.exit_code}: {said or "nothing said"})')
    return ''
