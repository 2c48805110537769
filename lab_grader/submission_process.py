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

from lab_grader.supervision import (describe, marked, reap_orphans, stop_all, Supervised,
                                    TERMINATE_GRACE)
import psutil

REAPER = str(Path(__file__).with_name('reaper.py'))


class Submission(Supervised):
    """The submission's command under a reaper; its exit status comes from the reaper."""

    def __init__(self, command, marker, output_path, cwd=None, env=None, memory_mb=0):
        self._status_read, status_write = os.pipe()
        os.set_blocking(self._status_read, False)
        self._status_text = ''
        self._exit_code = self._main = None
        # Isolated (-I): the standard library alone, nothing from the submission's folder.
        reaper = [sys.executable, '-I', REAPER, str(status_write), str(memory_mb),
                  str(os.getpid()), '--', *command]
        try:
            super().__init__(reaper, marker, output_path, cwd, env, pass_fds=(status_write,))
        finally:
            os.close(status_write)
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
                    self._main = int(line.split()[1])
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

    def _tree(self):
        """Return every running process of the submission: the reaper's descendants, marked."""
        found = {}
        try:
            for process in psutil.Process(self.process.pid).children(recursive=True):
                found[process.pid] = process
        except psutil.Error:
            pass
        for process in marked(self.marker):
            if process.pid != self.process.pid:
                found[process.pid] = process
        return [process for process in found.values() if _alive(process)]

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
