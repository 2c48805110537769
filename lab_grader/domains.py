"""
ROS domain IDs claimed for one process's use, so that runs side by side never see each other.

A domain is claimed by holding an exclusive lock on a file named after it, in a folder every
user of the machine shares: grade_lab claims one for each course it runs at once, and the test
suite one per worker, so none of them lands in a domain another is using. The lock goes with
the process, however it ends. Nodes started by hand claim nothing: a claim also avoids the
domain of the claiming process's own environment, where its user's other nodes most likely are.
"""

import fcntl
import os
from pathlib import Path
import random
import stat
import tempfile

# Linux gives each domain a range of ports; beyond domain 101 they may meet the ephemeral ports
# (ROS 2's "The ROS_DOMAIN_ID" page). Domain 0 is every unset machine's.
DOMAINS = range(1, 102)
LOCK_FOLDER = Path(tempfile.gettempdir()) / 'simple_robot_control-domains'


class NoDomainLeft(RuntimeError):
    """Every domain of the range is claimed already."""


class DomainClaim:
    """A domain held by this process until release() or its end."""

    def __init__(self, domain_id: int, descriptor: int):
        self.domain_id = domain_id
        self._descriptor = descriptor

    def release(self) -> None:
        """Let another process claim the domain."""
        if self._descriptor is not None:
            os.close(self._descriptor)
            self._descriptor = None


def claim_domain(avoid: tuple[int, ...] = ()) -> DomainClaim:
    """Claim a free domain in DOMAINS, starting at a random one; NoDomainLeft if none is."""
    avoid = set(avoid) | _own_domain()
    candidates = [domain for domain in DOMAINS if domain not in avoid]
    start = random.SystemRandom().randrange(len(candidates))
    LOCK_FOLDER.mkdir(exist_ok=True)
    try:
        LOCK_FOLDER.chmod(0o1777)
    except OSError:
        pass
    for domain in candidates[start:] + candidates[:start]:
        descriptor = _lock_file(LOCK_FOLDER / f'{domain}.lock')
        if descriptor is None:
            continue
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(descriptor)
            continue
        return DomainClaim(domain, descriptor)
    raise NoDomainLeft(f'all {len(candidates)} ROS domains of {DOMAINS.start} to '
                       f'{DOMAINS.stop - 1} are in use by other runs ({LOCK_FOLDER})')


def _lock_file(path):
    """
    Open a domain's lock file for writing, made usable by every user; None if it cannot be.

    Whatever stands there instead of a plain file (a folder, a link, a FIFO another user put
    there) makes its domain skipped, never an error. A file made here is opened to every user
    whatever the umask: one made 0644 by root would keep every other user out of its domain.
    """
    try:
        descriptor = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK
                             | os.O_CLOEXEC, 0o666)
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):
            raise OSError('not a file')
        if os.fstat(descriptor).st_uid == os.geteuid():
            os.fchmod(descriptor, 0o666)
    except OSError:
        os.close(descriptor)
        return None
    return descriptor


def _own_domain():
    text = os.environ.get('ROS_DOMAIN_ID', '')
    return {int(text)} if text.isdigit() else set()
