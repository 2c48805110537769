"""Waypoint files: whitespace-separated numbers read as triples x y theta (m, m, degrees)."""

import math
import os
from typing import NamedTuple

from simple_robot_control.input_files import read_text
from simple_robot_control.validation import Bounds, compact, describe, parse_decimal

# A course is at most this long, and every number of it has a range with meaning: positions
# within a thousand kilometres, headings within ten turns either way (a double holding 1e17
# degrees has no heading left in it once wrapped).
MAX_WAYPOINTS = 10_000
POSITION = Bounds(-1e6, 1e6)
HEADING_DEGREES = Bounds(-3600.0, 3600.0)
_FIELDS = (('x', POSITION), ('y', POSITION), ('theta (degrees)', HEADING_DEGREES))


class WaypointFileError(ValueError):
    """A waypoint file that cannot be used; the message is one line naming file, line, token."""


class Waypoint(NamedTuple):
    """A goal pose (x, y, theta); theta is in radians (the file gives degrees)."""

    x: float
    y: float
    theta: float


def parse_waypoints(text: str, source: str = '<string>') -> list[Waypoint]:
    """
    Parse waypoint text into a list of Waypoints.

    Any line breaks are allowed (one waypoint per line, or all on one line); blank lines and
    '#' comments are skipped. Numbers are plain ASCII decimals (12, -0.5, 1e3): Python would
    also take 5_0, non-ASCII digits, inf and nan, which a course file should never hold.
    Raises WaypointFileError for an empty course, a count that is not a multiple of three,
    a token that is not such a number, a position or heading out of range, or more than
    MAX_WAYPOINTS waypoints.
    """
    numbers = []
    for line_number, line in enumerate(text.splitlines(), start=1):
        for token in line.split('#', 1)[0].split():
            value = parse_decimal(token)
            if value is None:
                raise WaypointFileError(f'{source}:{line_number}: {describe(token)} is not a '
                                        'number (write plain decimals such as 2, -0.5 or 1e3)')
            numbers.append((value, line_number))
            if len(numbers) > 3 * MAX_WAYPOINTS:
                raise WaypointFileError(f'{source}:{line_number}: more than {MAX_WAYPOINTS:,} '
                                        'waypoints')
    if not numbers:
        raise WaypointFileError(f'{source}: no waypoints (the file has no numbers)')
    if len(numbers) % 3:
        raise WaypointFileError(
            f'{source}:{numbers[-1][1]}: {len(numbers)} numbers is not a whole number of '
            f'"x y theta" triples ({len(numbers) % 3} left over)')
    for index, (value, line_number) in enumerate(numbers):
        name, bounds = _FIELDS[index % 3]
        if not bounds.contains(value):
            raise WaypointFileError(f'{source}:{line_number}: waypoint {index // 3 + 1}: '
                                    f'{name} must be {bounds.text()}, got {compact(value)}')
    values = [value for value, _ in numbers]
    return [Waypoint(x, y, math.radians(theta))
            for x, y, theta in zip(values[0::3], values[1::3], values[2::3])]


def load_waypoints(path: str | os.PathLike) -> list[Waypoint]:
    """Read and parse a waypoint file."""
    path = os.fspath(path)
    return parse_waypoints(read_text(path, 'waypoint file', WaypointFileError), path)
