"""How the simulator holds, limits and times out velocity commands."""

import pytest
from stdr_lite.core.commands import (CommandOutcome, HeldCommands, SAFETY_ANGULAR_SPEED,
                                     SAFETY_LINEAR_SPEED, speed_limits)
from stdr_lite.core.state import StateTable


def held(robots, *limits, **options):
    return HeldCommands(StateTable.of_bodies([(0.0, 0.0, 0.0)] * robots), *limits, **options)


def test_commands_are_held_until_replaced():
    commands = held(2, 1.0, 2.0)
    commands.update(1, (0.5, 0.1, -0.25), now=0.0)
    linear, lateral, angular = commands.current(now=1000.0).T
    assert linear.tolist() == [0.0, 0.5]
    assert lateral.tolist() == [0.0, 0.1]
    assert angular.tolist() == [0.0, -0.25]


def test_commands_beyond_the_limits_are_clamped_along_their_direction():
    commands = held(1, 1.0, 2.0)
    command, outcome = commands.limited(-3.0, 4.0, 9.0)
    assert outcome is CommandOutcome.CLAMPED
    assert command == pytest.approx((-0.6, 0.8, 2.0))
    assert commands.limited(0.5, 0.0, -1.0) == ((0.5, 0.0, -1.0), CommandOutcome.APPLIED)


def test_without_limits_commands_go_as_given_short_of_the_safety_bound():
    assert speed_limits(0.0, 0.0) == (SAFETY_LINEAR_SPEED, SAFETY_ANGULAR_SPEED)
    assert speed_limits(500.0, 2.0) == (SAFETY_LINEAR_SPEED, 2.0)
    commands = held(1, 0.0, 0.0)
    assert commands.limited(4.0, 0.0, 4.7) == ((4.0, 0.0, 4.7), CommandOutcome.APPLIED)
    command, outcome = commands.limited(1e9, 0.0, -1e9)
    assert outcome is CommandOutcome.SAFETY_BOUND
    assert command == (SAFETY_LINEAR_SPEED, 0.0, -SAFETY_ANGULAR_SPEED)


def test_timeout_stops_a_robot_with_a_stale_command():
    commands = held(1, 1.0, 2.0, timeout=0.5)
    commands.update(0, (0.3, 0.0, 0.1), now=2.0)
    assert commands.current(2.5)[0].tolist() == [0.3, 0.0, 0.1]
    assert commands.current(2.51)[0].tolist() == [0.0, 0.0, 0.0]
