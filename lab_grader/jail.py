"""
What a submission may touch, made by its reaper as root before the command starts. Stdlib only.

The reaper (reaper.py) imports this when grade_lab runs as root; a Jail is JSON from
sandbox.py. With namespaces, the reaper's own child is the first process of a new process and
mount namespace (its network namespace is the course's already, inherited from grade_lab's
thread), and there, before the command starts:

- /dev/shm is a tmpfs of `disk_mb`, the only place the submission can write: /tmp is the host's
  /tmp seen through an overlay whose changes go there (what it may read of the host's /tmp, as
  any user may, it still reads; what it writes stays its own), /var/tmp a folder of it, and its
  home `/tmp/work` holds the files of `copy_in`;
- each folder of `cover` (one a uid other than root cannot pass, such as /root, holding the
  interpreter) is an empty tmpfs, and the paths of `expose` (those, and the submission's folder
  when it is below /tmp) are bound into the new tree again, read-only;
- then each folder of `hide` (the courses, the reports) that can still be reached is an empty
  read-only tmpfs, wherever it is (inside an exposed folder too);
- /proc shows the namespace's processes alone.

Then, with or without namespaces, the command runs as `uid` (no group, no capability, not even
in its bounding set, no_new_privs) with a process limit, in a session of its own.
"""

import ctypes
import os
from pathlib import Path
import resource

CLONE_NEWNS = 0x00020000
CLONE_NEWPID = 0x20000000
CLONE_NEWNET = 0x40000000
MS_RDONLY, MS_NOSUID, MS_NODEV, MS_NOEXEC = 1, 2, 4, 8
MS_REMOUNT, MS_BIND, MS_REC, MS_PRIVATE = 32, 4096, 16384, 1 << 18
_PR_CAPBSET_DROP = 24
_PR_SET_NO_NEW_PRIVS = 38
SANDBOX_HOME = '/tmp/work'
_LIBC = ctypes.CDLL(None, use_errno=True)


def _check(result, what):
    if result != 0:
        number = ctypes.get_errno()
        raise OSError(number, f'{what}: {os.strerror(number)}')


def unshare(flags: int) -> None:
    """Leave namespaces of the calling thread for new ones (Python 3.11 has no os.unshare)."""
    _check(_LIBC.unshare(flags), 'unshare')


def _mount(source, target, kind, flags, data=''):
    _check(_LIBC.mount(source.encode() if source else None, str(target).encode(),
                       kind.encode() if kind else None, ctypes.c_ulong(flags),
                       data.encode() if data else None), f'mount {target}')


def _bind_read_only(source, target):
    _mount(source, target, None, MS_BIND | MS_REC)
    _mount(None, target, None, MS_BIND | MS_REMOUNT | MS_RDONLY | MS_NOSUID | MS_NODEV)


def build_file_system(jail: dict) -> None:
    """In a new mount namespace, as root: the tmpfs, the hidden and covered folders, /proc."""
    uid = jail['uid']
    _mount(None, '/', None, MS_REC | MS_PRIVATE)
    # What is exposed again is held open now: once covered, its path no longer leads to it.
    exposed = [(path, os.open(path, os.O_PATH | os.O_CLOEXEC)) for path in jail['expose']]
    files = {name: Path(source).read_bytes() for name, source in jail['copy_in'].items()}
    _mount('tmpfs', '/dev/shm', 'tmpfs', MS_NOSUID | MS_NODEV,
           f'size={jail["disk_mb"]}m,mode=1777')
    for folder, mode in (('.tmp', 0o1777), ('.var_tmp', 0o1777), ('.overlay_work', 0o700)):
        os.mkdir(f'/dev/shm/{folder}', mode)
        os.chmod(f'/dev/shm/{folder}', mode)
    _mount('overlay', '/tmp', 'overlay', MS_NOSUID | MS_NODEV,
           'lowerdir=/tmp,upperdir=/dev/shm/.tmp,workdir=/dev/shm/.overlay_work')
    if os.path.isdir('/var/tmp'):
        _mount('/dev/shm/.var_tmp', '/var/tmp', None, MS_BIND)
    for folder in jail['cover']:
        _mount('tmpfs', folder, 'tmpfs', MS_NOSUID | MS_NODEV, 'size=4k,mode=0755')
    for path, descriptor in exposed:
        if os.path.isdir(f'/proc/self/fd/{descriptor}'):
            os.makedirs(path, mode=0o755, exist_ok=True)
        else:
            os.makedirs(os.path.dirname(path), mode=0o755, exist_ok=True)
            if not os.path.exists(path):
                os.close(os.open(path, os.O_CREAT | os.O_WRONLY, 0o644))
        _bind_read_only(f'/proc/self/fd/{descriptor}', path)
        os.close(descriptor)
    for folder in jail['hide']:
        if os.path.isdir(folder):
            _mount('tmpfs', folder, 'tmpfs', MS_RDONLY | MS_NOSUID | MS_NODEV | MS_NOEXEC,
                   'size=4k,mode=0')
    os.mkdir(SANDBOX_HOME, 0o700)
    for name, data in files.items():
        Path(SANDBOX_HOME, name).write_bytes(data)
        os.chown(Path(SANDBOX_HOME, name), uid, uid)
    os.chown(SANDBOX_HOME, uid, uid)
    _mount('proc', '/proc', 'proc', MS_NOSUID | MS_NODEV | MS_NOEXEC)


def drop_privileges(jail: dict) -> None:
    """In the command's process, just before exec: the uid alone, no way back to root."""
    uid = jail['uid']
    resource.setrlimit(resource.RLIMIT_NPROC, (jail['processes'], jail['processes']))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    last = int(Path('/proc/sys/kernel/cap_last_cap').read_text())
    for capability in range(last + 1):
        _LIBC.prctl(_PR_CAPBSET_DROP, capability, 0, 0, 0)
    os.setgroups([])
    os.setresgid(uid, uid, uid)
    os.setresuid(uid, uid, uid)
    _check(_LIBC.prctl(_PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0), 'no_new_privs')
