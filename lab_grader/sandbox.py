"""
How a course's submission is sealed off from the grader, the courses and other courses. No ROS.

Two ways (grade_lab --sandbox; the one a grading got is printed once at its start):

- `namespaces` (root, where the kernel lets root make namespaces): the course has a network
  namespace holding only loopback (grade_lab's thread of the course enters it, so its recorder,
  the simulator and the submission meet there and nowhere else); the submission runs as a uid
  of its own, without capabilities, in its own process and mount namespaces, its writes to
  /tmp, /dev/shm and /var/tmp its own (one tmpfs of --disk MB, its only writable place), the
  courses and reports hidden (jail.py);
- `same user` (grade_lab not root, or the kernel refuses namespaces, as Docker's default seccomp
  profile does): the submission runs as grade_lab's user; doc/grading.md says what then holds.

A uid of its own without namespaces is not offered: Jazzy's Fast DDS on the LOCALHOST range
talks through shared memory, which does not cross uids (measured: nothing delivered from root
to another uid, with or without a UDP-only profile), and outside a namespace of ours the range
must stay LOCALHOST. Inside one, the course's processes use the SUBNET range over UDP alone:
that subnet is the namespace's loopback.
"""

from collections.abc import Iterator
from contextlib import contextmanager
import ctypes
from dataclasses import dataclass, field
import fcntl
import json
import os
from pathlib import Path
import random
import socket
import stat
import struct
import subprocess
import sys
import threading

from lab_grader import jail as jails
import psutil

NAMESPACES, SAME_USER = 'namespaces', 'same user'
CHOICES = ('auto', 'namespaces', 'none')
# Submission uids: far above any system's users, groups and container ranges (subuid maps).
UID_RANGE = range(2_000_000_000, 2_001_000_000)
DISK_MB = 512
PROCESSES = 1024
_SIOCGIFFLAGS, _SIOCSIFFLAGS, _IFF_UP = 0x8913, 0x8914, 0x1


class SandboxError(RuntimeError):
    """The sandbox asked for cannot be had here; the message says why, in one line."""


def _namespace_problem() -> str:
    """Say why this process cannot make the namespaces a course needs ('' when it can)."""
    code = ('import ctypes, sys\n'
            f'flags = {jails.CLONE_NEWNET | jails.CLONE_NEWNS | jails.CLONE_NEWPID}\n'
            'libc = ctypes.CDLL(None, use_errno=True)\n'
            'if libc.unshare(flags):\n'
            '    import os; sys.exit(os.strerror(ctypes.get_errno()))\n')
    result = subprocess.run([sys.executable, '-I', '-c', code], capture_output=True, text=True,
                            timeout=30)
    return '' if result.returncode == 0 else (result.stderr.strip() or 'refused')


def choose_mode(requested: str) -> tuple[str, str]:
    """
    Return the sandbox to grade in (NAMESPACES or SAME_USER) and why not the stronger one.

    SandboxError when namespaces were asked for and cannot be had.
    """
    if requested == 'none':
        return SAME_USER, 'asked for by --sandbox none'
    if os.geteuid() != 0:
        problem = f'grade_lab runs as uid {os.geteuid()}, not root'
    else:
        problem = _namespace_problem()
        problem = problem and f'the kernel refuses namespaces here ({problem})'
    if not problem:
        return NAMESPACES, ''
    if requested == 'namespaces':
        raise SandboxError(f'--sandbox namespaces: {problem}')
    return SAME_USER, problem


def describe_mode(mode: str, disk_mb: int, why: str) -> str:
    """One line on what a run in this mode gets, for the start of a grading."""
    if mode == NAMESPACES:
        return ('namespaces: each submission runs as a uid of its own, without capabilities, '
                'in its own network (loopback only), process and mount namespaces, writing '
                f'only its own {disk_mb} MB /tmp')
    return (f"same user: each submission runs as grade_lab's own user ({why}); doc/grading.md "
            'says what holds then')


class UidPool:
    """Hands out uids no process runs as, none to two courses at once."""

    def __init__(self):
        self._taken = set()
        self._lock = threading.Lock()

    def take(self) -> int:
        in_use = set()
        for process in psutil.process_iter(['uids']):
            uids = process.info['uids']
            if uids is not None:
                in_use |= set(uids)
        with self._lock:
            while True:
                uid = random.SystemRandom().choice(UID_RANGE)
                if uid not in self._taken and uid not in in_use:
                    self._taken.add(uid)
                    return uid

    def give_back(self, uid: int) -> None:
        with self._lock:
            self._taken.discard(uid)


def untraversable_ancestor(path: str) -> str | None:
    """Return the first folder above path that other users cannot pass, or None."""
    parts = Path(path).parts
    for end in range(2, len(parts)):
        folder = str(Path(*parts[:end]))
        try:
            if not os.stat(folder).st_mode & stat.S_IXOTH:
                return folder
        except OSError:
            return None
    return None


def _within(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder.rstrip('/') + '/')


@dataclass
class SandboxPolicy:
    """What every course of a grading gets: the mode, the limits, what is hidden and needed."""

    mode: str = SAME_USER
    hidden: tuple[str, ...] = ()
    needed: tuple[str, ...] = ()
    disk_mb: int = DISK_MB
    processes: int = PROCESSES
    why: str = ''
    uids: UidPool = field(default_factory=UidPool)

    @property
    def sealed(self) -> bool:
        """Whether submissions run as a uid of their own, in namespaces of their own."""
        return self.mode == NAMESPACES

    def problem(self, cwd: str) -> str:
        """Say why a submission in cwd cannot be sandboxed as asked ('' when it can)."""
        if not self.sealed:
            return ''
        mode = os.stat(cwd).st_mode
        if mode & (stat.S_IROTH | stat.S_IXOTH) != stat.S_IROTH | stat.S_IXOTH:
            return (f"{cwd}: the submission's folder is mode {mode & 0o777:o}: the uid of its "
                    'own that it runs as cannot read it (chmod o+rx, as a checkout usually is)')
        for folder in self.hidden:
            for path in (cwd, *self.needed):
                if _within(path, folder):
                    return (f'{folder} must be hidden from the submissions, but holds {path}, '
                            'which they need: keep the courses and the reports apart')
        return ''

    def jail(self, uid: int, cwd: str, copy_in: dict[str, str]) -> dict:
        """Return what jail.py makes for one course's submission, running in cwd as uid."""
        needed = [os.path.realpath(path) for path in (cwd, *self.needed)]
        cover = sorted({folder for path in needed
                        if (folder := untraversable_ancestor(path)) is not None})
        expose = [path for path in dict.fromkeys(needed)
                  if any(_within(path, folder) for folder in cover)]
        return {'uid': uid, 'cwd': os.path.realpath(cwd), 'disk_mb': self.disk_mb,
                'processes': self.processes, 'hide': list(self.hidden), 'cover': cover,
                'expose': expose, 'copy_in': copy_in}


def jail_descriptor(jail: dict) -> int:
    """Return an inheritable descriptor holding the jail's JSON (no command line names it)."""
    memory = os.memfd_create('grade_lab-jail', 0)
    os.write(memory, json.dumps(jail).encode())
    os.lseek(memory, 0, os.SEEK_SET)
    return memory


def needed_paths(environment: dict) -> tuple[str, ...]:
    """Return the folders a submission needs to run this package's Python: interpreter, venv."""
    paths = {os.path.realpath(sys.base_prefix), os.path.realpath(sys.prefix)}
    for name in ('PYTHONPATH', 'AMENT_PREFIX_PATH', 'LD_LIBRARY_PATH'):
        paths |= {os.path.realpath(part) for part in environment.get(name, '').split(':')
                  if part and os.path.isdir(part)}
    return tuple(sorted(paths))


def processes_of(uid: int) -> list[psutil.Process]:
    """Return the running processes whose real, effective or saved uid is uid."""
    found = []
    for process in psutil.process_iter(['uids', 'status']):
        uids = process.info['uids']
        if uids is not None and uid in uids and process.info['status'] != psutil.STATUS_ZOMBIE:
            found.append(process)
    return found


@contextmanager
def network_of_its_own() -> Iterator[None]:
    """
    Put the calling thread, and what it starts, in a new network namespace with loopback up.

    A network namespace belongs to a thread: grade_lab's other courses stay where they are.
    The thread goes back to the host's namespace at the end; the course's goes with its last
    process and socket.
    """
    host = os.open('/proc/thread-self/ns/net', os.O_RDONLY | os.O_CLOEXEC)
    try:
        jails.unshare(jails.CLONE_NEWNET)
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as control:
            request = struct.pack('16sH', b'lo', 0)
            flags = struct.unpack('16sH', fcntl.ioctl(control, _SIOCGIFFLAGS, request)[:18])[1]
            fcntl.ioctl(control, _SIOCSIFFLAGS, struct.pack('16sH', b'lo', flags | _IFF_UP))
        yield
    finally:
        if ctypes.CDLL(None, use_errno=True).setns(host, jails.CLONE_NEWNET) != 0:
            raise OSError(ctypes.get_errno(), 'setns back to the host network')
        os.close(host)
