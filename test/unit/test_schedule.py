"""Control ticks on a fixed grid of odometry stamp time."""

import pytest
from waypoint_lab.lifecycle import ControlSchedule

MS = 1_000_000


def ticks(schedule, stamps):
    return [(stamp, elapsed) for stamp in stamps
            if (elapsed := schedule.due(stamp)) is not None]


def test_first_stamp_is_a_tick_of_one_period():
    assert ControlSchedule(50 * MS).due(7 * MS) == 50 * MS


def test_mean_rate_is_kept_when_the_odometry_period_does_not_divide_it():
    found = ticks(ControlSchedule(50 * MS), range(0, 1000 * MS, 20 * MS))
    assert [stamp // MS for stamp, _ in found[:5]] == [0, 60, 100, 160, 200]
    assert len(found) == 20
    assert sum(elapsed for _, elapsed in found[1:]) == found[-1][0] - found[0][0]


def test_slow_odometry_makes_every_stamp_a_tick_with_its_true_interval():
    found = ticks(ControlSchedule(10 * MS), range(0, 500 * MS, 100 * MS))
    assert [elapsed // MS for _, elapsed in found] == [10, 100, 100, 100, 100]


def test_repeated_stamp_is_not_a_second_tick():
    schedule = ControlSchedule(50 * MS)
    assert schedule.due(0) is not None
    assert schedule.due(0) is None


def test_period_must_be_positive():
    with pytest.raises(ValueError, match='control period must be positive'):
        ControlSchedule(0)
