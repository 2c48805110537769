"""
Typed access to the values of a description read from YAML: every complaint names its key.

Robot files, robot lists and spawn resources are checked through one reader, so each value is
judged by one rule and refused in one line, `<file>: <key>: <problem>`. No ROS here.
"""

from simple_robot_control.validation import (Bounds, compact, describe, FINITE, is_finite_number,
                                             is_ros_name, ROS_NAME_RULE)


class RobotFileError(ValueError):
    """A robot description that cannot be used; the message is one line naming file and key."""


class FieldReader:
    """Typed access to YAML values; every complaint names the file and the key."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, problem: str) -> None:
        """Raise RobotFileError naming the file and the key."""
        raise RobotFileError(f'{self.source}: {key}: {problem}')

    def mapping(self, value: object, key: str) -> dict:
        """Return value if it is a mapping."""
        if not isinstance(value, dict):
            self.fail(key or 'top level', f'expected a mapping, got {describe(value)}')
        return value

    def sequence(self, data: dict, key: str, where: str) -> list:
        """Return data's list at key (empty if absent)."""
        value = data.get(key) or []
        if not isinstance(value, list):
            self.fail(f'{where}.{key}' if where else key,
                      f'expected a list, got {describe(value)}')
        return value

    def number(self, data: dict, key: str, where: str, bounds: Bounds = FINITE) -> float:
        """Return data's finite number at key, within bounds."""
        name = f'{where}.{key}' if where else key
        if key not in data:
            self.fail(name, 'missing')
        value = data[key]
        if not is_finite_number(value):
            self.fail(name, f'expected a finite number, got {describe(value)}')
        if not bounds.contains(value):
            self.fail(name, f'must be {bounds.text()}, got {compact(value)}')
        return float(value)

    def count(self, data: dict, key: str, where: str, bounds: Bounds) -> int:
        """Return data's whole number at key, within bounds."""
        value = self.number(data, key, where, bounds)
        if value != int(value):
            self.fail(f'{where}.{key}', f'expected a whole number, got {compact(value)}')
        return int(value)

    def name(self, data: dict, key: str, where: str, default: str | None = None) -> str:
        """Return data's ROS name at key (default if absent)."""
        value = data.get(key, default)
        if not is_ros_name(value):
            self.fail(f'{where}.{key}', f'expected {ROS_NAME_RULE}, got {describe(value)}')
        return value

    def pose(self, data: dict, key: str, where: str, position: Bounds, heading: Bounds) -> tuple:
        """Return (x, y, theta) of a pose mapping {x, y, theta}; absent, the origin."""
        name = f'{where}.{key}' if where else key
        pose = self.mapping(data.get(key, {'x': 0, 'y': 0, 'theta': 0}), name)
        return (self.number(pose, 'x', name, position), self.number(pose, 'y', name, position),
                self.number(pose, 'theta', name, heading))

    def choice(self, data: dict, key: str, where: str, choices: tuple, default: str) -> str:
        """Return data's value at key, one of choices (default if absent)."""
        value = data.get(key, default)
        if value not in choices:
            self.fail(f'{where}.{key}', f'expected one of {", ".join(choices)}, got '
                      f'{describe(value)}')
        return value
