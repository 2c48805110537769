"""
The text of robot_status messages, as the lab specifies them: written and read here alone.

STARTED <x> <y> <theta>, WAYPOINT <n> <x> <y> <theta>, FINISHED, ABORTED <n> <x> <y> <theta>;
metres, and theta in degrees (the lab's unit). The planning coursework adds UNREACHABLE <n> <x>
<y> <theta>: goal n given up as one no path reaches (the pose where it was said), the run going
on to the next; the lab's own courses have no such goal. Poses given to and taken from this
module are (x, y, theta in radians).
"""

from dataclasses import dataclass
import math
import re

from simple_robot_control.validation import parse_decimal

STARTED, WAYPOINT, FINISHED, ABORTED = 'STARTED', 'WAYPOINT', 'FINISHED', 'ABORTED'
UNREACHABLE = 'UNREACHABLE'
# The statuses that name a goal, and what each says of it.
NUMBERED = (WAYPOINT, ABORTED, UNREACHABLE)
ENDINGS = (FINISHED, ABORTED)
# The longest status is well under this: WAYPOINT, a number and a pose of three decimals.
MAX_STATUS_LENGTH = 200
_WAYPOINT_NUMBER = re.compile(r'^[1-9][0-9]{0,8}$', re.ASCII)


def _pose_text(pose):
    x, y, theta = pose
    return f'{x:.3f} {y:.3f} {math.degrees(theta):.2f}'


def started(pose: tuple) -> str:
    return f'{STARTED} {_pose_text(pose)}'


def waypoint_reached(number: int, pose: tuple) -> str:
    return f'{WAYPOINT} {number} {_pose_text(pose)}'


def finished() -> str:
    return FINISHED


def aborted(number: int, pose: tuple) -> str:
    return f'{ABORTED} {number} {_pose_text(pose)}'


def unreachable(number: int, pose: tuple) -> str:
    return f'{UNREACHABLE} {number} {_pose_text(pose)}'


@dataclass(frozen=True)
class Status:
    """A robot_status message read back: its kind, waypoint number and pose where it has them."""

    kind: str
    number: int | None = None
    pose: tuple | None = None

    @property
    def ends_run(self) -> bool:
        return self.kind in ENDINGS


def parse_status(text: str) -> Status | None:
    """
    Read a robot_status text; None if it is not one this module writes.

    Text from another node is input: its numbers must be plain finite decimals, a waypoint
    number a whole number from 1, and the whole text no longer than any status can be.
    """
    if len(text) > MAX_STATUS_LENGTH:
        return None
    words = text.split()
    if not words or words[0] not in (STARTED, FINISHED, *NUMBERED):
        return None
    kind, rest = words[0], words[1:]
    if kind == FINISHED:
        return Status(kind) if not rest else None
    number = None
    if kind in NUMBERED:
        if not rest or not _WAYPOINT_NUMBER.match(rest[0]):
            return None
        number, rest = int(rest[0]), rest[1:]
    values = [parse_decimal(word) for word in rest]
    if len(values) != 3 or None in values:
        return None
    x, y, degrees = values
    return Status(kind, number, (x, y, math.radians(degrees)))
