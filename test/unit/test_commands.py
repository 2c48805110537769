"""How the simulator holds, clamps, rejects and times out velocity commands."""

import math

from stdr_lite.core.commands import CommandBuffer


def test_commands_are_held_until_replaced():
    commands = CommandBuffer(2, 1.0, 2.0)
    commands.update(1, 0.5, -0.25, now=0.0)
    linear, angular = commands.current(now=1000.0)
    assert linear.tolist() == [0.0, 0.5]
    assert angular.tolist() == [0.0, -0.25]


def test_commands_beyond_the_limits_are_clamped():
    commands = CommandBuffer(1, 1.0, 2.0)
    assert commands.exceeds_limits(-3.0, 0.0)
    assert commands.update(0, -3.0, 9.0, now=0.0)
    assert [array[0] for array in commands.current(0.0)] == [-1.0, 2.0]


def test_non_finite_commands_are_ignored():
    commands = CommandBuffer(1, 1.0, 2.0)
    commands.update(0, 0.3, 0.1, now=0.0)
    for bad in ((math.nan, 0.0), (0.0, math.inf), (-math.inf, math.nan)):
        assert not commands.update(0, *bad, now=1.0)
    assert [array[0] for array in commands.current(1.0)] == [0.3, 0.1]


def test_timeout_stops_a_robot_with_a_stale_command():
    commands = CommandBuffer(1, 1.0, 2.0, timeout=0.5)
    commands.update(0, 0.3, 0.1, now=2.0)
    assert [array[0] for array in commands.current(2.5)] == [0.3, 0.1]
    assert [array[0] for array in commands.current(2.51)] == [0.0, 0.0]
