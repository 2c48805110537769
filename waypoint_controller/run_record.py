"""
Recorded runs: robot_status and odometry as JSON lines, one object per line.

The first line describes the run: {"course": name, "waypoints": [[x, y, theta], ...],
"distance_tolerance": m, "angle_tolerance": rad}. Every later line is either a pose,
{"t": s, "pose": [x, y, theta]}, or a status message, {"t": s, "status": text}, where t is
the odometry stamp time in seconds and angles are radians (REP-103).
"""

from dataclasses import dataclass, field
import json
import math
import os

from waypoint_controller.waypoints import Waypoint


class RunRecordError(ValueError):
    """A record that cannot be read; the message is one line naming the file and line."""


@dataclass
class RunRecord:
    """Everything a picture of the run needs."""

    course: str
    waypoints: list
    distance_tolerance: float
    angle_tolerance: float
    times: list = field(default_factory=list)
    poses: list = field(default_factory=list)
    statuses: list = field(default_factory=list)

    @property
    def result(self):
        """Return FINISHED or ABORTED from the last status, or None while the run is unfinished."""
        if self.statuses and self.statuses[-1][1].split()[0] in ('FINISHED', 'ABORTED'):
            return self.statuses[-1][1].split()[0]
        return None

    @property
    def duration(self):
        """Return the seconds from STARTED to the last status message."""
        if len(self.statuses) < 2:
            return 0.0
        return self.statuses[-1][0] - self.statuses[0][0]


class RunRecordWriter:
    """Writes a record line by line, so a run cut short still leaves a readable file."""

    def __init__(self, path, course, waypoints, distance_tolerance, angle_tolerance):
        self._stream = open(path, 'w', encoding='utf-8')
        self._write({'course': course,
                     'waypoints': [[w.x, w.y, w.theta] for w in waypoints],
                     'distance_tolerance': distance_tolerance,
                     'angle_tolerance': angle_tolerance})

    def pose(self, time, pose):
        self._write({'t': time, 'pose': list(pose)})

    def status(self, time, text):
        self._write({'t': time, 'status': text})

    def close(self):
        self._stream.close()

    def _write(self, entry):
        self._stream.write(json.dumps(entry) + '\n')


def load_run(path):
    """Read a record written by RunRecordWriter; RunRecordError names what is wrong."""
    path = os.fspath(path)
    try:
        with open(path, encoding='utf-8') as stream:
            lines = stream.read().splitlines()
    except OSError as error:
        raise RunRecordError(f'{path}: cannot read run record: {error.strerror}') from None
    except UnicodeDecodeError as error:
        raise RunRecordError(f'{path}: not a text file ({error.reason})') from None
    if not lines:
        raise RunRecordError(f'{path}: empty run record')
    header = _entry(path, 1, lines[0])
    try:
        record = RunRecord(
            course=str(header['course']),
            waypoints=[Waypoint(*_finite(path, 1, values, 3)) for values in header['waypoints']],
            distance_tolerance=_finite(path, 1, [header['distance_tolerance']], 1)[0],
            angle_tolerance=_finite(path, 1, [header['angle_tolerance']], 1)[0])
    except (KeyError, TypeError) as error:
        raise RunRecordError(f'{path}:1: not a run header ({error!r} missing or wrong)') from None
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        entry = _entry(path, number, line)
        time = _finite(path, number, [entry.get('t')], 1)[0]
        if 'pose' in entry:
            record.times.append(time)
            record.poses.append(tuple(_finite(path, number, entry['pose'], 3)))
        elif isinstance(entry.get('status'), str) and entry['status'].strip():
            record.statuses.append((time, entry['status']))
        else:
            raise RunRecordError(f'{path}:{number}: neither a pose nor a status: {line!r}')
    return record


def _entry(path, number, line):
    try:
        entry = json.loads(line)
    except json.JSONDecodeError as error:
        raise RunRecordError(f'{path}:{number}: not JSON ({error.msg}): {line!r}') from None
    if not isinstance(entry, dict):
        raise RunRecordError(f'{path}:{number}: not a JSON object: {line!r}')
    return entry


def _finite(path, number, values, count):
    """Check that values is a list of count finite numbers and return them as floats."""
    if (not isinstance(values, list) or len(values) != count
            or not all(isinstance(value, (int, float)) and not isinstance(value, bool)
                       and math.isfinite(value) for value in values)):
        raise RunRecordError(f'{path}:{number}: expected {count} finite number'
                             f'{"s" if count > 1 else ""}, got {values!r}')
    return [float(value) for value in values]
