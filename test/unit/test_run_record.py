"""Run records: what the writer writes, the reader reads back; bad records are one-line errors."""

import json
import math

import pytest
from waypoint_controller.run_record import (load_run, MAX_LINE_CHARACTERS, MAX_RECORD_BYTES,
                                            RunRecordError, RunRecordWriter, StatusClock)
from waypoint_controller.waypoints import MAX_WAYPOINTS, Waypoint

HEADER = {'course': 'square.txt', 'waypoints': [[1.0, 2.0, 0.5]], 'distance_tolerance': 0.1,
          'angle_tolerance': 0.087}


def test_written_record_reads_back(tmp_path):
    path = tmp_path / 'run.jsonl'
    writer = RunRecordWriter(path, 'square.txt', [Waypoint(1.0, 2.0, 0.5), Waypoint(3, 4, -1)],
                             0.1, math.radians(5.0), complain=pytest.fail)
    writer.status(0.0, 'STARTED 0.000 0.000 0.00')
    writer.pose(0.0, (0.0, 0.0, 0.0))
    writer.pose(0.02, (0.01, 0.0, 0.1))
    writer.status(4.5, 'FINISHED')
    writer.close()
    record = load_run(path)
    assert record.course == 'square.txt'
    assert record.waypoints == [Waypoint(1.0, 2.0, 0.5), Waypoint(3.0, 4.0, -1.0)]
    assert (record.distance_tolerance, record.angle_tolerance) == (0.1, math.radians(5.0))
    assert record.times == [0.0, 0.02]
    assert record.poses == [(0.0, 0.0, 0.0), (0.01, 0.0, 0.1)]
    assert record.statuses == [(0.0, 'STARTED 0.000 0.000 0.00'), (4.5, 'FINISHED')]
    assert (record.result, record.duration) == ('FINISHED', 4.5)


def test_unfinished_record_has_no_result(tmp_path):
    path = tmp_path / 'run.jsonl'
    path.write_text(json.dumps(HEADER) + '\n' + '{"t": 0.0, "status": "STARTED 0 0 0"}\n')
    assert load_run(path).result is None


@pytest.mark.parametrize('lines, message', [
    ([], 'run.jsonl: empty run record'),
    (['{"course": "x"'], 'run.jsonl:1: not JSON'),
    (['[1, 2]'], 'run.jsonl:1: not a JSON object'),
    (['{"course": "x"}'], "run.jsonl:1: not a run header (KeyError('waypoints')"),
    ([json.dumps(dict(HEADER, waypoints=[[1.0, 2.0]]))],
     'run.jsonl:1: waypoint: expected 3 finite'),
    ([json.dumps(HEADER), '{"t": 1.0, "pose": [1.0, NaN, 0.0]}'],
     'run.jsonl:2: pose: expected 3 finite numbers, got [1, nan, 0]'),
    ([json.dumps(HEADER), '{"t": "soon", "status": "FINISHED"}'],
     "run.jsonl:2: t: expected 1 finite number, got ['soon']"),
    ([json.dumps(HEADER), '{"t": 1.0, "pose": [1e308, 2.0, 0.0]}'],
     'run.jsonl:2: pose must be in [-1000000, 1000000], got 1e+308'),
    ([json.dumps(dict(HEADER, waypoints=[[1.0, 1e308, 0.0]]))],
     'run.jsonl:1: waypoint must be in [-1000000, 1000000], got 1e+308'),
    ([json.dumps(dict(HEADER, distance_tolerance=1e308))],
     'run.jsonl:1: distance_tolerance must be in (0, 10], got 1e+308'),
    ([json.dumps(dict(HEADER, angle_tolerance=-1.0))],
     'run.jsonl:1: angle_tolerance must be in (0, 3.14159265359], got -1'),
    ([json.dumps(HEADER), '', '{"t": 1.0, "speed": 3}'],
     'run.jsonl:3: neither a pose nor a status'),
    ([json.dumps(HEADER), '{"t": 1.0, "pose": ' + '[' * 5000 + ']' * 5000 + '}'],
     'run.jsonl:2: JSON nested too deeply'),
    ([json.dumps(dict(HEADER, waypoints=[[1.0, 2.0, 0.0]] * (MAX_WAYPOINTS + 1)))],
     'run.jsonl:1: a course of 10,001 waypoints (at most 10,000)'),
    ([json.dumps(HEADER), '{"t": 1.0, "status": "' + 'x' * (MAX_LINE_CHARACTERS + 1) + '"}'],
     'run.jsonl:2: a line of'),
])
def test_bad_record_is_one_line_naming_file_and_line(tmp_path, lines, message):
    path = tmp_path / 'run.jsonl'
    path.write_text(''.join(line + '\n' for line in lines))
    with pytest.raises(RunRecordError) as raised:
        load_run(path)
    assert message in str(raised.value)
    assert '\n' not in str(raised.value)


def test_missing_record_is_named(tmp_path):
    with pytest.raises(RunRecordError, match='nothing.jsonl: cannot read run record'):
        load_run(tmp_path / 'nothing.jsonl')


def drive(clock, poses, start=0.0, step=0.02):
    for index, pose in enumerate(poses):
        clock.odometry(start + index * step, pose)


def test_status_is_dated_by_the_odometry_showing_its_pose():
    clock = StatusClock()
    standing = [(1.0, 2.0, 0.0)] * 5
    moving = [(1.0 + 0.01 * k, 2.0, 0.0) for k in range(1, 20)]
    drive(clock, standing + moving)
    assert clock.now == pytest.approx(23 * 0.02)
    assert clock.date('STARTED 1.000 2.000 0.00') == 0.0
    assert clock.date('WAYPOINT 1 1.100 2.000 0.00') == pytest.approx(14 * 0.02)
    assert clock.date('FINISHED') == pytest.approx(14 * 0.02)


def test_a_status_before_any_odometry_waits_for_it():
    clock = StatusClock()
    assert clock.now is None and clock.date('STARTED 1.000 2.000 0.00') is None
    drive(clock, [(1.0, 2.0, 0.0)] * 3, start=15.0)
    assert clock.date('STARTED 1.000 2.000 0.00') == 15.0


def test_status_without_a_matching_pose_is_dated_now():
    clock = StatusClock()
    drive(clock, [(1.0, 2.0, 0.0), (1.1, 2.0, 0.0)])
    assert clock.date('WAYPOINT 1 5.000 5.000 0.00') == pytest.approx(0.02)
    assert clock.date('ABORTED 2 1.000 2.000 0.00') == pytest.approx(0.02)


def test_heading_matches_across_the_wrap_and_repeated_stamps_are_ignored():
    clock = StatusClock()
    assert clock.odometry(0.0, (0.0, 0.0, math.pi))
    assert not clock.odometry(0.0, (9.0, 9.0, 0.0))
    clock.odometry(0.02, (0.0, 0.0, 1.0))
    assert clock.date('WAYPOINT 1 0.000 0.000 -180.00') == 0.0


def test_an_interrupted_record_is_read_up_to_its_last_whole_line(tmp_path):
    path = tmp_path / 'run.jsonl'
    whole = [json.dumps(HEADER), '{"t": 0.0, "pose": [1.0, 2.0, 0.0]}',
             '{"t": 0.0, "status": "STARTED 1.000 2.000 0.00"}']
    path.write_text('\n'.join(whole) + '\n{"t": 0.02, "pose": [1.0, 2.')
    record = load_run(path)
    assert record.cut_short_line == 4
    assert record.poses == [(1.0, 2.0, 0.0)] and len(record.statuses) == 1
    path.write_text('\n'.join(whole) + '\n')
    assert load_run(path).cut_short_line is None


def test_a_bad_line_inside_a_record_is_still_an_error(tmp_path):
    path = tmp_path / 'run.jsonl'
    path.write_text(json.dumps(HEADER) + '\n{"t": 0.0, "pose": [1.0,\n'
                    '{"t": 0.0, "pose": [1, 2, 3]}')
    with pytest.raises(RunRecordError, match='run.jsonl:2: not JSON'):
        load_run(path)


def test_statuses_that_are_no_statuses_are_left_out_and_counted(tmp_path):
    path = tmp_path / 'run.jsonl'
    lines = [json.dumps(HEADER), '{"t": 0.0, "status": "STARTED 1.000 2.000 0.00"}',
             '{"t": 0.5, "status": "hello from another node"}',
             '{"t": 0.6, "status": "WAYPOINT -1 1 2 3"}', '{"t": 1.0, "status": "FINISHED"}']
    path.write_text('\n'.join(lines) + '\n')
    record = load_run(path)
    assert [text for _, text in record.statuses] == ['STARTED 1.000 2.000 0.00', 'FINISHED']
    assert record.skipped_lines == [3, 4]


def test_a_write_that_fails_ends_the_recording_not_the_run(tmp_path):
    complaints = []
    writer = RunRecordWriter('/dev/full', 'c.txt', [Waypoint(1.0, 2.0, 0.0)], 0.1, 0.1,
                             complain=complaints.append)
    writer.pose(0.0, (1.0, 2.0, 0.0))
    writer.close()
    assert complaints == ['/dev/full: cannot write the record (No space left on device); '
                          'recording stops here, the run goes on']


def test_a_record_stops_growing_at_its_bound(tmp_path, monkeypatch):
    monkeypatch.setattr('waypoint_controller.run_record.MAX_RECORD_BYTES', 2000)
    complaints = []
    path = tmp_path / 'run.jsonl'
    writer = RunRecordWriter(path, 'c.txt', [Waypoint(1.0, 2.0, 0.0)], 0.1, 0.1,
                             complain=complaints.append)
    for step in range(200):
        writer.pose(0.02 * step, (1.0, 2.0, 0.0))
    writer.close()
    assert len(complaints) == 1 and 'the record reached' in complaints[0]
    assert path.stat().st_size <= 2000 and load_run(path).poses
    assert MAX_RECORD_BYTES == 64 << 20
