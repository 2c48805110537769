"""robot_status texts as the lab specifies them, written and read back by one module."""

import math

import pytest
from waypoint_lab.status import (aborted, finished, parse_status, started, Status,
                                 unreachable, waypoint_reached)


def test_messages_carry_poses_with_theta_in_degrees():
    assert started((1.0, 2.0, 0.0)) == 'STARTED 1.000 2.000 0.00'
    assert waypoint_reached(3, (4.5, -1.25, math.pi / 2)) == 'WAYPOINT 3 4.500 -1.250 90.00'
    assert aborted(2, (0.0, 0.0, -math.pi)) == 'ABORTED 2 0.000 0.000 -180.00'
    assert finished() == 'FINISHED'
    assert unreachable(4, (1.0, 1.0, 0.0)) == 'UNREACHABLE 4 1.000 1.000 0.00'


@pytest.mark.parametrize('text, status', [
    ('STARTED 1.000 -2.500 90.00', Status('STARTED', None, (1.0, -2.5, math.pi / 2))),
    ('WAYPOINT 3 0.5 0.25 -45', Status('WAYPOINT', 3, (0.5, 0.25, -math.pi / 4))),
    ('ABORTED 2 0 0 180', Status('ABORTED', 2, (0.0, 0.0, math.pi))),
    ('FINISHED', Status('FINISHED')),
    ('UNREACHABLE 4 1 1 0', Status('UNREACHABLE', 4, (1.0, 1.0, 0.0))),
])
def test_texts_are_read_back(text, status):
    parsed = parse_status(text)
    assert (parsed.kind, parsed.number) == (status.kind, status.number)
    assert parsed.pose == (pytest.approx(status.pose) if status.pose else None)
    assert parsed.ends_run == (status.kind in ('FINISHED', 'ABORTED'))


@pytest.mark.parametrize('text', ['', 'WAYPOINT 3 x y z', 'WAYPOINT 1.000 2.000 3.00',
                                  'FINISHED early', 'STOPPED 1 2 3', 'STARTED 1 2',
                                  'STARTED nan nan nan', 'WAYPOINT -1 1 2 3', 'WAYPOINT 0 1 2 3',
                                  'WAYPOINT \u0662 1 2 3', 'STARTED 1 2 inf', 'STARTED 1e999 2 3',
                                  'STARTED 1 2 3 ' + ' ' * 300, 'ABORTED 01 1 2 3',
                                  'UNREACHABLE 1 2', 'UNREACHABLE 0 1 2 3'])
def test_other_texts_are_not_statuses(text):
    assert parse_status(text) is None


def test_what_is_written_reads_back_to_the_same_pose():
    pose = (1.2345, -0.5, math.radians(123.45))
    assert parse_status(waypoint_reached(7, pose)).pose == pytest.approx(pose, abs=1e-3)
