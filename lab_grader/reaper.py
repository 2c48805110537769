"""
The parent of one course's submission, that every process it starts comes back to.

    python -I reaper.py STATUS_FD MEMORY_MB PARENT_PID JAIL_FD -- COMMAND ...

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

JAIL_FD (-1: none) holds a Jail in JSON (jail.py), read from a descriptor because a command line
is anyone's to read: then the command runs as the jail's uid, and with namespaces the reaper's
child is the first process of the submission's own namespaces, the one that reaps and reports,
which nothing the submission does can end without ending everything in it.
"""

import ctypes
import json
import os
import resource
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jail as jails  # noqa: E402  (a sibling, found from here: -I puts no folder on the path)

_PR_SET_PDEATHSIG = 1
_PR_SET_CHILD_SUBREAPER = 36


def _prctl(option, value):
    try:
        ctypes.CDLL(None, use_errno=True).prctl(option, value, 0, 0, 0)
    except (OSError, AttributeError):
        pass


def _start(command, memory_mb, jail):
    """In the forked child: a session of its own, default signals, the limits, the uid, exec."""
    os.setsid()
    for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(number, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_SETMASK, [])
    if memory_mb:
        limit = memory_mb << 20
        resource.setrlimit(resource.RLIMIT_DATA, (limit, limit))
    if jail:
        jails.drop_privileges(jail)
        os.chdir(jail['cwd'])
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


def main(argv: list[str]) -> int:
    status_fd, memory_mb, parent, jail_fd, separator, *command = argv
    if separator != '--' or not command:
        print('usage: python -I reaper.py STATUS_FD MEMORY_MB PARENT_PID JAIL_FD -- COMMAND ...',
              file=sys.stderr)
        return 2
    # Not for the command: a submission writing `started 1` here would hide its processes.
    os.set_inheritable(int(status_fd), False)
    status = os.fdopen(int(status_fd), 'w', buffering=1)
    jail = None
    if int(jail_fd) >= 0:
        with os.fdopen(int(jail_fd), 'rb') as stream:
            jail = json.loads(stream.read())
    _prctl(_PR_SET_CHILD_SUBREAPER, 1)
    _prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    for number in (signal.SIGINT, signal.SIGHUP):
        signal.signal(number, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, lambda *_: (_kill_descendants(), os._exit(0)))
    if os.getppid() != int(parent):
        return 0  # grade_lab died before the death signal was set: nothing to run for
    if jail:
        try:
            jails.unshare(jails.CLONE_NEWNS | jails.CLONE_NEWPID)
            first = os.fork()
        except OSError as error:
            status.write(f'cannot start {command[0]}: {error.strerror}\n')
            return 0
        if first:
            return _outside(first)
        _prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
        try:
            jails.build_file_system(jail)
        except OSError as error:
            status.write(f'cannot start {command[0]}: the sandbox: {error}\n')
            os._exit(0)
    return _reap(status, command, int(memory_mb), jail)


def _outside(first):
    """Outside the namespaces: wait for their first process; end it (and all in them) on TERM."""
    signal.signal(signal.SIGTERM, lambda *_: (os.kill(first, signal.SIGKILL), os._exit(0)))
    while True:
        try:
            os.waitpid(first, 0)
            return 0
        except InterruptedError:
            continue


def _reap(status, command, memory_mb, jail):
    try:
        child = os.fork()
    except OSError as error:
        status.write(f'cannot start {command[0]}: {error.strerror}\n')
        return 0
    if child == 0:
        try:
            _start(command, memory_mb, jail)
        except OSError as error:
            os.write(status.fileno(), f'cannot start {command[0]}: {error.strerror}\n'.encode())
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
