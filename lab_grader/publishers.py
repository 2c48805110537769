"""
Who publishes on a course's topics: the simulator, the submission, or another program. No ROS.

rclpy hands a message no publisher identity, but the graph names every publisher with its DDS
endpoint id. Fast DDS (Jazzy's middleware) writes its vendor id (01.0f) in the id's first two
bytes and the low 16 bits of the publishing process's id in bytes 4 and 5 (little-endian), so
a publisher is traced to a process of the run or to none of them.
"""

from collections.abc import Iterable
from dataclasses import dataclass

FAST_DDS_VENDOR = b'\x01\x0f'


@dataclass(frozen=True)
class Publisher:
    """A publisher the graph shows: its topic, its node, and its DDS endpoint id."""

    topic: str
    node: str
    gid: bytes


def process_bits(gid: bytes) -> int | None:
    """Return the low 16 bits of the publishing process's id, or None for another vendor's."""
    gid = bytes(gid)
    if len(gid) < 6 or gid[:2] != FAST_DDS_VENDOR:
        return None
    return int.from_bytes(gid[4:6], 'little')


def of_processes(gid: bytes, pids: Iterable[int]) -> bool:
    """Whether the publisher is one of these processes'."""
    bits = process_bits(gid)
    return bits is not None and bits in {pid & 0xFFFF for pid in pids}


@dataclass
class Intruders:
    """Publishers found where they have no business: fouls (the submission's) and strangers."""

    fouls: list[str]
    strangers: list[str]


def find_intruders(simulator_topics: Iterable[Publisher], status_topic: Iterable[Publisher],
                   simulator_pid: int, submission_pids: Iterable[int],
                   running: Iterable[int]) -> Intruders:
    """
    Name the publishers that have no business where they publish.

    On the simulator's topics, any but the simulator's; on robot_status, any but the
    submission's. submission_pids are every process the submission has been seen to run, and
    running every process that runs now. A publisher is the submission's when it is one of
    its processes, or of no process that still runs (the graph shows a publisher a while
    after its process ended, and the domain was empty when the run began); it is a stranger's
    when it is a running process that is none of the run's.
    """
    submission_pids = set(submission_pids)
    outside = {pid & 0xFFFF for pid in running} - {pid & 0xFFFF for pid in submission_pids}
    found = Intruders([], [])

    def submissions(publisher):
        return process_bits(publisher.gid) not in outside

    for publisher in simulator_topics:
        if of_processes(publisher.gid, [simulator_pid]):
            continue
        if submissions(publisher):
            found.fouls.append(f'{publisher.topic} was published by node {publisher.node!r} of '
                               'the submission (only the simulator publishes it)')
        else:
            found.strangers.append(_stranger(publisher))
    for publisher in status_topic:
        if not submissions(publisher):
            found.strangers.append(_stranger(publisher))
    return found


def _stranger(publisher):
    return (f'another program (node {publisher.node!r}, a process outside this run) published '
            f"{publisher.topic} in the course's ROS domain")
