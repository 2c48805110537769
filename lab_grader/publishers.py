"""
Who publishes on a course's topics: the simulator, the submission, or another program. No ROS.

What a publisher says of itself (its DDS endpoint id, its node's name) is the publisher's own
claim, so identity rests on two facts it cannot forge. The simulator's endpoints are those the
graph showed before the submission started (the domain held the simulator and the grader alone
then); any other endpoint on the simulator's topics is an intruder. Who an intruder is, the
kernel says: every DDS participant of a domain holds UDP sockets on the domain's ports (RTPS's
port mapping), and /proc names each socket's owner (its uid, and through the open files its
process). Where a course has a network namespace of its own, nothing outside the run can hold
such a socket there, and every intruder is the submission.
"""

from collections.abc import Iterable
from dataclasses import dataclass
import os
from pathlib import Path

# RTPS's well-known ports (the DDS interoperability wire protocol, 9.6.1.1): PB + DG * domain
# and up, a participant's ports within the domain's DG.
PORT_BASE, DOMAIN_GAIN = 7400, 250
# What rmw says of an endpoint's node before the node's own announcement has come: a foul seen
# that early is named without it (the run ends at once, it does not wait for the name).
UNNAMED_NODE = '_NODE_NAME_UNKNOWN_'


@dataclass(frozen=True)
class Publisher:
    """A publisher the graph shows: its topic, its node, and its DDS endpoint id."""

    topic: str
    node: str
    gid: bytes


@dataclass(frozen=True)
class Owner:
    """A process holding a socket on a domain's ports: its pid (0 if unseen) and uid."""

    pid: int
    uid: int


def domain_ports(domain_id: int) -> range:
    """Return the UDP ports of a domain's participants."""
    start = PORT_BASE + DOMAIN_GAIN * domain_id
    return range(start, start + DOMAIN_GAIN)


def socket_owners(domain_id: int, proc: Path = Path('/proc')) -> set[Owner]:
    """
    Return the owners of the UDP sockets bound to a domain's ports (the participants' holders).

    A socket's uid comes from the kernel's table; its process from the open files, where this
    process may read them (all as root; its user's own otherwise: pid 0 when unseen).
    """
    inodes = {}
    for table in ('udp', 'udp6'):
        try:
            lines = (proc / 'net' / table).read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            try:
                port = int(fields[1].rsplit(':', 1)[1], 16)
                uid, inode = int(fields[7]), int(fields[9])
            except (IndexError, ValueError):
                continue
            if port in domain_ports(domain_id) and inode:
                inodes[inode] = uid
    owners = {}
    if inodes:
        for pid, inode in _socket_inodes(proc):
            if inode in inodes:
                owners[inode] = Owner(pid, inodes[inode])
    return set(owners.values()) | {Owner(0, uid) for inode, uid in inodes.items()
                                   if inode not in owners}


def _socket_inodes(proc):
    for entry in os.listdir(proc):
        if not entry.isdigit():
            continue
        try:
            descriptors = os.listdir(proc / entry / 'fd')
        except OSError:
            continue
        for descriptor in descriptors:
            try:
                target = os.readlink(proc / entry / 'fd' / descriptor)
            except OSError:
                continue
            if target.startswith('socket:['):
                yield int(entry), int(target[8:-1])


def strangers(owners: Iterable[Owner], run_pids: Iterable[int],
              submission_uid: int | None) -> list[str]:
    """
    Name the owners that are none of the run's: not its processes, nor its submission's uid.

    An owner whose process is unseen (another user's, to a grader that is not root) is named by
    its uid, unless that uid is the submission's own.
    """
    run_pids = set(run_pids)
    found = []
    for owner in sorted(owners, key=lambda owner: (owner.pid, owner.uid)):
        if owner.pid in run_pids or (submission_uid is not None
                                     and owner.uid == submission_uid):
            continue
        if owner.pid == 0 and owner.uid == os.geteuid():
            continue  # a socket of this user's closed as it was read
        who = f'pid {owner.pid}, uid {owner.uid}' if owner.pid else f'uid {owner.uid}'
        found.append(f'another program ({who}, a process outside this run) joined the '
                     "course's ROS domain")
    return found


@dataclass
class Intruders:
    """Publishers found where they have no business: fouls (the submission's) and strangers."""

    fouls: list[str]
    strangers: list[str]


def find_intruders(simulator_topics: Iterable[Publisher], simulator_gids: Iterable[bytes],
                   outsiders: list[str]) -> Intruders:
    """
    Name the publishers that have no business where they publish.

    On the simulator's topics, any endpoint but the simulator's own. When the run's domain holds
    no outsider, such a publisher is the submission's, a foul; otherwise nobody can tell whose
    it is, and the outsiders are named instead: the run is no test of the submission.
    """
    simulator_gids = {bytes(gid) for gid in simulator_gids}
    if outsiders:
        return Intruders([], list(outsiders))
    return Intruders([f'{publisher.topic} was published by {_whose(publisher.node)} (only the '
                      'simulator publishes it)'
                      for publisher in simulator_topics
                      if bytes(publisher.gid) not in simulator_gids], [])


def _whose(node):
    """Name the submission's node, or say the graph has not named it yet (rmw's placeholder)."""
    return ('the submission (a node the graph had not named yet)' if UNNAMED_NODE in node
            else f'node {node!r} of the submission')
