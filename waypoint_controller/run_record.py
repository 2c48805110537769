"""
Recorded runs: robot_status and odometry as JSON lines, one object per line.

The first line describes the run: {"course": name, "waypoints": [[x, y, theta], ...],
"distance_tolerance": m, "angle_tolerance": rad}. Every later line is either a pose,
{"t": s, "pose": [x, y, theta]}, or a status message, {"t": s, "status": text}, where t is
the odometry stamp time in seconds and angles are radians (REP-103).
"""

from collections import deque
from dataclasses import dataclass, field
import json
import math
import os

from simple_robot_control.input_files import read_text
from simple_robot_control.validation import Bounds, describe, is_finite_number
from waypoint_controller.status import FINISHED, parse_status, STARTED, WAYPOINT
from waypoint_controller.waypoints import MAX_WAYPOINTS, POSITION, Waypoint


# robot_status prints x and y to 1 mm and theta to 0.01 degree; a pose matches within rounding.
POSITION_ROUNDING = 0.0006
HEADING_ROUNDING = math.radians(0.006)
# A record holds a pose per odometry stamp: an hour at 50 Hz is about 11 MB.
MAX_RECORD_BYTES = 64 << 20
# The header holds the course: its line is the longest, about 60 bytes a waypoint.
MAX_LINE_CHARACTERS = 60 * MAX_WAYPOINTS + 1000
RECENT_POSES = 2000
# What a record may hold: poses on a map (headings within ten turns either way), the goal set's
# tolerances as a course may set them, times within a year.
POSE = (POSITION, POSITION, Bounds(-20.0 * math.pi, 20.0 * math.pi))
DISTANCE_TOLERANCE = Bounds(0.0, 10.0, low_open=True)
ANGLE_TOLERANCE = Bounds(0.0, math.pi, low_open=True)
TIME = Bounds(-3.2e7, 3.2e7)


class StatusClock:
    """
    Date robot_status messages by the odometry stamp of the pose they report.

    A status message carries no stamp and may arrive after later odometry (discovery, queues),
    so the time of arrival is not the time of the event. The reported pose is matched against
    recent odometry instead: the message is dated by the first stamp of the latest stretch of
    odometry showing that pose. FINISHED has no pose and shares the last message's date;
    ABORTED comes at the end of a stall, so it is dated by the latest odometry. A status that
    comes before any odometry (a monitor started after the controller hears its STARTED first)
    has no date yet: date() says None, and dated_late() gives it its date once odometry came.
    """

    def __init__(self):
        self._recent = deque(maxlen=RECENT_POSES)
        self._last_date = None
        # Statuses heard before any odometry, in the order they came.
        self._waiting = []

    def odometry(self, time, pose):
        """Note the pose at a stamp; return False for a repeated stamp, which is ignored."""
        if self._recent and self._recent[-1][0] == time:
            return False
        self._recent.append((time, pose))
        return True

    @property
    def now(self):
        """Return the latest odometry stamp, in seconds; None before any odometry."""
        return self._recent[-1][0] if self._recent else None

    def date(self, text):
        """Return the time at which the status message text was true; None before odometry."""
        if not self._recent:
            self._waiting.append(text)
            return None
        status = parse_status(text)
        if status is not None and status.kind == FINISHED:
            return self._last_date
        self._last_date = self.now
        if status is not None and status.kind in (STARTED, WAYPOINT):
            self._last_date = self._first_stamp_showing(*status.pose)
        return self._last_date

    def dated_late(self):
        """Return (date, text) of each status that waited for odometry, once it has come."""
        if not self._recent:
            return []
        waiting, self._waiting = self._waiting, []
        return [(self.date(text), text) for text in waiting]

    def _first_stamp_showing(self, x, y, theta):
        first = None
        for time, (pose_x, pose_y, pose_theta) in reversed(self._recent):
            if (abs(pose_x - x) <= POSITION_ROUNDING and abs(pose_y - y) <= POSITION_ROUNDING
                    and abs(math.remainder(pose_theta - theta, math.tau)) <= HEADING_ROUNDING):
                first = time
            elif first is not None:
                break
        return self.now if first is None else first


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
    cut_short_line: int | None = None
    skipped_lines: list = field(default_factory=list)

    @property
    def result(self):
        """Return FINISHED or ABORTED from the last status, or None while the run is unfinished."""
        last = parse_status(self.statuses[-1][1]) if self.statuses else None
        return last.kind if last is not None and last.ends_run else None

    def reported_poses(self, kind):
        """Return the poses (theta in radians) reported by the status messages of one kind."""
        statuses = (parse_status(text) for _, text in self.statuses)
        return [status.pose for status in statuses
                if status is not None and status.kind == kind and status.pose is not None]

    @property
    def duration(self):
        """Return the seconds from STARTED to the last status message."""
        if len(self.statuses) < 2:
            return 0.0
        return self.statuses[-1][0] - self.statuses[0][0]


class RunRecordWriter:
    """
    Writes a record line by line, so a run cut short still leaves a readable file.

    A write that fails (a full disk) or a record that would outgrow MAX_RECORD_BYTES ends the
    recording, not the run: complain(line) is told once, and later writes are dropped. Opening
    the file raises OSError.
    """

    def __init__(self, path, course, waypoints, distance_tolerance, angle_tolerance,
                 complain):
        self._path, self._complain = path, complain
        self._stream = open(path, 'w', encoding='utf-8')
        self._written = 0
        self._write({'course': course,
                     'waypoints': [[w.x, w.y, w.theta] for w in waypoints],
                     'distance_tolerance': distance_tolerance,
                     'angle_tolerance': angle_tolerance})

    def pose(self, time, pose):
        self._write({'t': time, 'pose': list(pose)})

    def status(self, time, text):
        self._write({'t': time, 'status': text})

    def close(self):
        if self._stream is not None:
            self._end(None)

    def _write(self, entry):
        if self._stream is None:
            return
        line = json.dumps(entry) + '\n'
        if self._written + len(line) > MAX_RECORD_BYTES:
            self._end(f'{self._path}: the record reached {MAX_RECORD_BYTES >> 20} MB; recording '
                      'stops here, the run goes on')
            return
        try:
            self._stream.write(line)
            self._stream.flush()
        except OSError as error:
            self._end(f'{self._path}: cannot write the record ({error.strerror}); recording '
                      'stops here, the run goes on')
            return
        self._written += len(line)

    def _end(self, problem):
        stream, self._stream = self._stream, None
        try:
            stream.close()
        except OSError:
            pass
        if problem:
            self._complain(problem)


def export_run(record: RunRecord, path: str | os.PathLike, complain) -> None:
    """Write a run (read from a bag, say) as JSON lines: its poses, then its statuses."""
    writer = RunRecordWriter(path, record.course, record.waypoints, record.distance_tolerance,
                             record.angle_tolerance, complain)
    entries = [(time, 0, pose) for time, pose in zip(record.times, record.poses)]
    entries += [(time, 1, text) for time, text in record.statuses]
    for time, is_status, value in sorted(entries, key=lambda entry: entry[:2]):
        if is_status:
            writer.status(time, value)
        else:
            writer.pose(time, value)
    writer.close()


def load_run(path: str | os.PathLike) -> RunRecord:
    """
    Read a record written by RunRecordWriter; RunRecordError names what is wrong.

    A run that was interrupted may leave its last line half written: that line is left out,
    and cut_short_line says which it was. A status line whose text is no status (a node other
    than the controller spoke on robot_status) is left out too, its number in skipped_lines.
    """
    path = os.fspath(path)
    text = read_text(path, 'run record', RunRecordError, MAX_RECORD_BYTES)
    lines = text.splitlines()
    if not lines:
        raise RunRecordError(f'{path}: empty run record')
    cut_short = None
    if not text.endswith('\n') and len(lines) > 1 and not _is_json(lines[-1]):
        cut_short = len(lines)
        lines.pop()
    header = _entry(path, 1, lines[0])
    try:
        record = RunRecord(
            course=str(header['course']),
            waypoints=[Waypoint(*_bounded(path, 1, values, POSE, 'waypoint'))
                       for values in header['waypoints']],
            distance_tolerance=_bounded(path, 1, [header['distance_tolerance']],
                                        (DISTANCE_TOLERANCE,), 'distance_tolerance')[0],
            angle_tolerance=_bounded(path, 1, [header['angle_tolerance']], (ANGLE_TOLERANCE,),
                                     'angle_tolerance')[0])
    except (KeyError, TypeError) as error:
        raise RunRecordError(f'{path}:1: not a run header ({error!r} missing or wrong)') from None
    record.cut_short_line = cut_short
    if len(record.waypoints) > MAX_WAYPOINTS:
        raise RunRecordError(f'{path}:1: a course of {len(record.waypoints):,} waypoints (at most '
                             f'{MAX_WAYPOINTS:,})')
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        entry = _entry(path, number, line)
        time = _bounded(path, number, [entry.get('t')], (TIME,), 't')[0]
        if 'pose' in entry:
            record.times.append(time)
            record.poses.append(tuple(_bounded(path, number, entry['pose'], POSE, 'pose')))
        elif not isinstance(entry.get('status'), str):
            raise RunRecordError(f'{path}:{number}: neither a pose nor a status')
        elif parse_status(entry['status']) is None:
            record.skipped_lines.append(number)
        else:
            record.statuses.append((time, entry['status']))
    return record


def _is_json(line):
    try:
        json.loads(line)
    except (json.JSONDecodeError, RecursionError):
        return False
    return True


def _entry(path, number, line):
    if len(line) > MAX_LINE_CHARACTERS:
        raise RunRecordError(f'{path}:{number}: a line of {len(line):,} characters (at most '
                             f'{MAX_LINE_CHARACTERS:,})')
    try:
        entry = json.loads(line)
    except json.JSONDecodeError as error:
        raise RunRecordError(f'{path}:{number}: not JSON ({error.msg})') from None
    except RecursionError:
        raise RunRecordError(f'{path}:{number}: JSON nested too deeply') from None
    if not isinstance(entry, dict):
        raise RunRecordError(f'{path}:{number}: not a JSON object')
    return entry


def _bounded(path, number, values, bounds, name):
    """Check that values is a list of numbers, each within its bounds; return them as floats."""
    count = len(bounds)
    if not isinstance(values, list) or len(values) != count or not all(
            map(is_finite_number, values)):
        raise RunRecordError(f'{path}:{number}: {name}: expected {count} finite number'
                             f'{"s" if count > 1 else ""}, got {describe(values)}')
    for value, bound in zip(values, bounds):
        if not bound.contains(value):
            raise RunRecordError(f'{path}:{number}: {bound.problem(name, value)}')
    return [float(value) for value in values]
