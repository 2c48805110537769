"""The question-and-answer dialogue of the lab's move_robot tool, free of ROS."""

from collections.abc import Callable
import math

from simple_robot_control.validation import describe, parse_decimal


class EndOfInput(Exception):
    """The user closed standard input (Ctrl-D or the end of a piped file)."""


def format_pose(x: float, y: float, theta: float) -> str:
    """Write the pose as the lab prints it, with theta in degrees."""
    return f'Current position, x: {x:.3f}, y: {y:.3f}, theta: {math.degrees(theta):.2f}'


def ask_number(prompt: str, read_line: Callable[[], str | None], write: Callable[[str], object],
               minimum: float | None = None) -> float:
    """
    Ask until the answer is a finite number (at least minimum, if given); return it.

    read_line returns a line without its newline, or None at end of input.
    """
    while True:
        write(prompt)
        answer = read_line()
        if answer is None:
            raise EndOfInput()
        text = answer.strip()
        value = parse_decimal(text)
        if value is None:
            write(f'Not a finite number: {describe(text)}. Please try again.\n')
        elif minimum is not None and value < minimum:
            write(f'Must be at least {minimum:g}, got {text}. Please try again.\n')
        else:
            return value


def ask_motion(read_line: Callable[[], str | None], write: Callable[[str], object]
               ) -> tuple[float, float, float]:
    """Ask the lab's three questions; return (linear m/s, angular rad/s, duration s)."""
    linear = ask_number('Enter desired linear velocity: ', read_line, write)
    angular_degrees = ask_number('Enter desired rotational velocity: ', read_line, write)
    duration = ask_number('Enter desired duration: ', read_line, write, minimum=0.0)
    return linear, math.radians(angular_degrees), duration
