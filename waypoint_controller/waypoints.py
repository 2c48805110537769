"""Waypoint files: whitespace-separated numbers read as triples x y theta (m, m, degrees)."""

from dataclasses import dataclass
import math
import os


class WaypointFileError(ValueError):
    """A waypoint file that cannot be used; the message is one line naming file, line, token."""


@dataclass(frozen=True)
class Waypoint:
    """A goal pose; theta is in radians (the file gives degrees)."""

    x: float
    y: float
    theta: float


def parse_waypoints(text, source='<string>'):
    """
    Parse waypoint text into a list of Waypoints.

    Any line breaks are allowed (one waypoint per line, or all on one line); blank lines and
    '#' comments are skipped. Raises WaypointFileError for an empty course, a count that is not
    a multiple of three, a token that is not a number, or NaN/infinity.
    """
    numbers = []
    last_line = 0
    for line_number, line in enumerate(text.splitlines(), start=1):
        for token in line.split('#', 1)[0].split():
            try:
                value = float(token)
            except ValueError:
                raise WaypointFileError(
                    f'{source}:{line_number}: {token!r} is not a number') from None
            if not math.isfinite(value):
                raise WaypointFileError(
                    f'{source}:{line_number}: {token!r} is not a finite number') from None
            numbers.append(value)
            last_line = line_number
    if not numbers:
        raise WaypointFileError(f'{source}: no waypoints (the file has no numbers)')
    if len(numbers) % 3:
        raise WaypointFileError(
            f'{source}:{last_line}: {len(numbers)} numbers is not a whole number of '
            f'"x y theta" triples ({len(numbers) % 3} left over)')
    return [Waypoint(x, y, math.radians(theta))
            for x, y, theta in zip(numbers[0::3], numbers[1::3], numbers[2::3])]


def load_waypoints(path):
    """Read and parse a waypoint file."""
    path = os.fspath(path)
    try:
        with open(path, encoding='utf-8') as stream:
            text = stream.read()
    except OSError as error:
        raise WaypointFileError(f'{path}: cannot read waypoint file: {error.strerror}') from None
    except UnicodeDecodeError as error:
        raise WaypointFileError(f'{path}: not a text file ({error.reason})') from None
    return parse_waypoints(text, path)
