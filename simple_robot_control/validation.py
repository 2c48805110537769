"""
Checks of numbers and names from users, each giving one line that says what is wrong.

Plain Python, no ROS: the nodes, the file readers and the simulation core all use these, so a
value is judged by the same rule wherever it enters.
"""

from dataclasses import dataclass
import math
import re

# A plain ASCII decimal: 12, -0.5, .5, 1e3. Python's float() also takes 5_0, non-ASCII digits,
# 'inf' and 'nan', which no number typed or written for this package should be.
_DECIMAL = re.compile(r'^[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?$', re.ASCII)
# ROS 2 names (REP-144 / rcl's rules): a token starts with a letter and holds ASCII letters,
# digits and underscores; no double underscore, no trailing underscore.
_TOKEN = re.compile(r'^[A-Za-z][A-Za-z0-9_]*$')


class ConfigError(Exception):
    """A configuration problem reported as one line, ending the program with exit code 2."""


def require(condition: object, message: str) -> None:
    """Raise ConfigError(message) unless condition holds."""
    if not condition:
        raise ConfigError(message)


def compact(value: object) -> str:
    """Write a number briefly (12 significant digits at most), anything else as repr."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return repr(value)
    return f'{value:.12g}'


def describe(value: object) -> str:
    """
    Name a value for an error message without echoing what may be a whole file.

    Numbers and short one-line texts are shown; anything longer is described by its kind and
    size, so a wrong file given as input never has its contents copied into a log.
    """
    if isinstance(value, bool) or value is None:
        return repr(value)
    if isinstance(value, (int, float)):
        return compact(value)
    if isinstance(value, str):
        if len(value) <= 24 and value.isprintable():
            return repr(value)
        return f'a text of {len(value)} characters'
    if isinstance(value, dict):
        return f'a mapping of {len(value)} keys'
    if isinstance(value, (list, tuple)):
        if len(value) <= 6 and not any(isinstance(item, (dict, list, tuple)) for item in value):
            return '[' + ', '.join(describe(item) for item in value) + ']'
        return f'a list of {len(value)} items'
    return f'a {type(value).__name__}'


def shorten(text: str, length: int = 40) -> str:
    """Return text, or its beginning and end around '...' when longer than length."""
    if len(text) <= length:
        return text
    keep = (length - 3) // 2
    return f'{text[:keep]}...{text[-keep:]}'


def parse_decimal(text: str) -> float | None:
    """Return the finite number a plain ASCII decimal stands for, or None if it is not one."""
    if not _DECIMAL.match(text):
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def is_finite_number(value: object) -> bool:
    """Whether value is an int or float (not a bool) that is neither NaN nor infinite."""
    return (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value))


@dataclass(frozen=True)
class Bounds:
    """
    An interval a number must lie in; either end may be open or absent.

    Every bounded quantity of the package has finite limits that make sense for it, so a
    value such as 1e308 m/s is refused where it enters rather than failing deep inside.
    """

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False

    def text(self) -> str:
        """Describe the interval in words a user reads: 'positive', '>= 0', 'in (0, 10]'."""
        if self.high is None:
            if self.low is None:
                return 'a finite number'
            if self.low == 0.0:
                return 'positive' if self.low_open else '>= 0'
            return f'{">" if self.low_open else ">="} {compact(self.low)}'
        if self.low is None:
            return f'{"<" if self.high_open else "<="} {compact(self.high)}'
        return (f'in {"(" if self.low_open else "["}{compact(self.low)}, '
                f'{compact(self.high)}{")" if self.high_open else "]"}')

    def contains(self, value: float) -> bool:
        """Whether value is finite and within the interval."""
        if not is_finite_number(value):
            return False
        if self.low is not None and (value < self.low or (self.low_open and value == self.low)):
            return False
        return self.high is None or not (value > self.high
                                         or (self.high_open and value == self.high))

    def problem(self, name: str, value: object) -> str | None:
        """Return 'NAME must be ..., got VALUE', or None when value lies within."""
        if self.contains(value):
            return None
        return f'{name} must be {self.text()}, got {describe(value)}'


FINITE = Bounds()
POSITIVE = Bounds(0.0, None, low_open=True)
NON_NEGATIVE = Bounds(0.0)


ROS_NAME_RULE = ('a ROS name (ASCII letters, digits and underscores, starting with a letter, '
                 "no '__', not ending in '_')")


def is_ros_name(name: object) -> bool:
    """
    Whether name can be a robot or frame name in ROS topics.

    Names become topic and frame tokens (/<name>/odom, <name>/base_link), so they must follow
    the rules of a ROS name token.
    """
    return (isinstance(name, str) and bool(_TOKEN.match(name)) and '__' not in name
            and not name.endswith('_'))


def ros_name_problem(name: object, what: str) -> str | None:
    """Return 'WHAT must be a ROS name ..., got NAME', or None if name is one."""
    return None if is_ros_name(name) else f'{what} must be {ROS_NAME_RULE}, got {describe(name)}'


def topic_name_problem(name: object, what: str) -> str | None:
    """Return a line saying why name is no topic name (ROS names joined by '/'), or None."""
    tokens = name[1:].split('/') if isinstance(name, str) and name.startswith('/') else (
        name.split('/') if isinstance(name, str) else [None])
    if all(is_ros_name(token) for token in tokens):
        return None
    return (f"{what} must be a topic name (ROS names joined by '/', as /map or "
            f'robot0/map), got {describe(name)}')
