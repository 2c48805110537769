"""
What a node parameter is and which values it takes: plain data, no ROS.

A node's table of ParameterSpecs lives in a module that loads in a tenth of a second, so the
values given on a command line are judged (early_parameters.py) before the node's own code,
rclpy, numpy and numba are loaded; the node judges them again by the same rules when it
declares them (parameters.py), and whenever they are set while it runs.
"""

import array
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
import difflib

from simple_robot_control.validation import (Bounds, compact, describe, is_finite_number,
                                             ros_name_problem, topic_name_problem)

# What rclpy itself declares or reads on every node, besides the node's own parameters.
RCLPY_PARAMETERS = ('use_sim_time', 'start_type_description_service')
RCLPY_PREFIXES = ('qos_overrides.',)
# The kind of value each default stands for, in words. A list default is a list of doubles, a
# tuple one of strings (an empty one has no type of its own in rclpy).
_KINDS = {bool: 'a boolean (true or false)', int: 'an integer', float: 'a number',
          str: 'a string', list: 'a list of numbers', tuple: 'a list of strings'}
# rclpy gives array values as lists, or as array.array where they came in a message.
_SEQUENCES = (list, tuple, array.array)


@dataclass(frozen=True)
class ParameterSpec:
    """
    One node parameter: its default, a description with units, and what values it accepts.

    bounds limits a number, choices a string, ros_name makes a string a ROS name (a robot or
    frame name that goes into topics), topic a topic name; constraints adds words for what
    none of those can say.
    A parameter is read-only unless tunable, in which case `ros2 param set` may change it while
    the node runs, under the same checks as at start.
    """

    name: str
    default: object
    description: str
    bounds: Bounds | None = None
    choices: tuple = ()
    ros_name: bool = False
    topic: bool = False
    constraints: str = ''
    tunable: bool = False

    def constraint_text(self) -> str:
        words = [self.bounds.text()] if self.bounds else []
        if self.choices:
            words.append(' | '.join(self.choices))
        if self.ros_name:
            words.append('a ROS name')
        if self.topic:
            words.append('a topic name' + (' or empty' if self.default == '' else ''))
        if self.constraints:
            words.append(self.constraints)
        return '; '.join(words)

    def problem(self, value: object) -> str | None:
        """Return one line saying why value (of the right type) is not acceptable, or None."""
        if self.bounds is not None:
            return self.bounds.problem(self.name, value)
        if self.choices and value not in self.choices:
            return f'{self.name} must be one of {", ".join(self.choices)}, got {value!r}'
        if self.ros_name:
            return ros_name_problem(value, self.name)
        if self.topic:
            # A topic whose default is empty is optional: empty is none.
            return None if value == '' == self.default else topic_name_problem(value, self.name)
        if isinstance(self.default, list) and not all(is_finite_number(item) for item in value):
            return f'{self.name} must hold finite numbers, got {[compact(v) for v in value]}'
        return None

    def as_declared_type(self, value: object) -> object:
        """
        Return value as this parameter's type, or None when it is not of that type.

        A whole number is taken for a double (users type `3`, `ros2 param set x 3` sends an
        INTEGER), and whole numbers for a list of doubles; nothing else is converted.
        """
        kind = type(self.default)
        if kind is float and _is_integer(value):
            return float(value)
        if kind is list and isinstance(value, _SEQUENCES):
            if all(_is_integer(item) for item in value):
                return [float(item) for item in value]
            return list(value) if all(type(item) is float for item in value) else None
        if kind is tuple and isinstance(value, _SEQUENCES):
            return tuple(value) if all(type(item) is str for item in value) else None
        return value if type(value) is kind else None

    def type_problem(self, value: object) -> str:
        """Say in one line that value is not of this parameter's type."""
        return f'parameter {self.name}: expected {_KINDS[type(self.default)]}, got ' \
               f'{describe(value)}'

    def help_line(self) -> str:
        default = (list(self.default) if isinstance(self.default, tuple)
                   else self.default if self.default != '' else "''")
        constraints = self.constraint_text()
        extra = ', '.join(part for part in (constraints, 'tunable' if self.tunable else '')
                          if part)
        return f'  {self.name} [default {default}]: {self.description}' + (
            f' ({extra})' if extra else '')


def unknown_problem(node_name: str, given: Iterable[str], specs: Sequence[ParameterSpec]
                    ) -> str | None:
    """Return one line naming the first given parameter that node_name does not take, or None."""
    known = [spec.name for spec in specs]
    unknown = sorted(name for name in given if name not in known
                     and name not in RCLPY_PARAMETERS and not name.startswith(RCLPY_PREFIXES))
    if not unknown:
        return None
    name = unknown[0]
    close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
    hint = f'; did you mean {close[0]}?' if close else f'; {node_name} takes {", ".join(known)}'
    return f'unknown parameter {name!r} for {node_name}{hint}'


def _is_integer(value) -> bool:
    return type(value) is int
