"""
The parent of one course's submission, that every process it starts comes back to.

    python -I reaper.py STATUS_FD MEMORY_MB PARENT_PID -- COMMAND ...

grade_lab starts this small program for each course; it makes itself a child subreaper (Linux),
so that a process of the submission that detaches (a double fork, setsid, env -i, a new process
group) is adopted by it rather than by init, and stays among its descendants, where grade_lab
finds and ends it. It runs the command in a session of its own with SIGINT and SIGTERM at their
defaults, each of its processes limited to MEMORY_MB of writable memory (RLIMIT_DATA; 0: no
limit), writes
`started <pid>` on STATUS_FD, then `exit <status>` when the command's own process ends (or
`cannot start <why>`), and
then reaps until grade_lab ends it. If grade_lab itself dies, so does this, taking the
submission with it. Nothing but the standard library: it starts in a few milliseconds.
"""

import ctypes
import os
import resource
import signal
import sys

_PR_SET_PDEATHSIG = 1
_PR_SET_CHILD_SUBREAPER = 36


def _prctl(option, value):
    try:
        ctypes.CDLL(None, use_errno=True).prctl(option, value, 0, 0, 0)
    except (OSError, AttributeError):
        pass


def _start(command, memory_mb):
    """In the forked child: a session of its own, default signals, the memory limit, exec."""
    os.setsid()
    for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(number, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_SETMASK, [])
    if memory_mb:
        limit = memory_mb << 20
        resource.setrlimit(resource.RLIMIT_DATA, (limit, limit))
    os.execvp(command[0], command)


def _kill_descendants():
    """End every process below this one (they are all the submission's), as it ends."""
    for _ in range(50):
        found = False
        for entry in os.listdir('/proc'):
            if not entry.isdigit():
                continue
            try:
                with open(f'/proc/{entry}/stat') as stat:
                    parent = int(stat.read().rsplit(')', 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            if parent == os.getpid():
                found = True
                try:
                    os.kill(int(entry), signal.SIGKILL)
                except OSError:
                    pass
        try:
            while os.waitpid(-1, os.WNOHANG)[0]:
                pass
        except ChildProcessError:
            pass
        if not found:
            return


def main(argv):
    status_fd, memory_mb, parent, separator, *command = argv
    if separator != '--' or not command:
        print('usage: python -I reaper.py STATUS_FD MEMORY_MB PARENT_PID -- COMMAND ...',
              file=sys.stderr)
        return 2
    status = os.fdopen(int(status_fd), 'w', buffering=1)
    _prctl(_PR_SET_CHILD_SUBREAPER, 1)
    _prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    for number in (signal.SIGINT, signal.SIGHUP):
        signal.signal(number, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, lambda *_: (_kill_descendants(), os._exit(0)))
    if os.getppid() != int(parent):
        return 0  # grade_lab died before the death signal was set: nothing to run for
    try:
        child = os.fork()
    except OSError as error:
        status.write(f'cannot start {command[0]}: {error.strerror}\n')
        return 0
    if child == 0:
        try:
            _start(command, int(memory_mb))
        except OSError as error:
            os.write(int(status_fd), f'cannot start {command[0]}: {error.strerror}\n'.encode())
        os._exit(127)
    status.write(f'started {child}\n')
    while True:
        try:
            pid, code = os.wait()
        except ChildProcessError:
            signal.pause()
            continue
        except InterruptedError:
            continue
        if pid == child:
            status.write(f'exit {os.waitstatus_to_exitcode(code)}\n')


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
