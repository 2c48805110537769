"""
Shortest paths of a robot that may drive forwards and backwards (Reeds and Shepp, 1990).

With |v| <= V, |omega| <= W and no acceleration limit, a Reeds-Shepp path at the turning radius
R = V / W, driven at full speed, is time-optimal whenever position matters: arcs at full rate,
straights, cusps where the robot reverses. Reeds and Shepp proved the shortest path is one of
48 words of at most five segments; each word has a closed form (their formulas 8.1 to 8.11),
tried here on the goal and on its mirror images (reversing time, reflecting left and right,
reading the path backwards). The tests check the lengths against OMPL's ReedsSheppStateSpace.

Pure Python on purpose: a pose query costs tens of microseconds and needs no compiled
dependency, and rosdep has no key for OMPL's Python bindings.
"""

from collections.abc import Sequence
from dataclasses import dataclass
import math

from simple_robot_control.pose import wrap_angle

LEFT, STRAIGHT, RIGHT = 1, 0, -1
HALF_PI = 0.5 * math.pi
_SLACK = 1e-10


@dataclass(frozen=True)
class Segment:
    """One piece of a path: steering LEFT, STRAIGHT or RIGHT; length in radii, < 0 backwards."""

    steering: int
    length: float


def _left_straight_left(x, y, phi):
    xi, eta = x - math.sin(phi), y - 1.0 + math.cos(phi)
    u, t = math.hypot(xi, eta), math.atan2(eta, xi)
    v = wrap_angle(phi - t)
    return (t, u, v) if t >= -_SLACK and v >= -_SLACK else None


def _left_straight_right(x, y, phi):
    rho = math.hypot(x + math.sin(phi), y - 1.0 - math.cos(phi))
    if rho < 2.0:
        return None
    u = math.sqrt((rho - 2.0) * (rho + 2.0))
    t = wrap_angle(math.atan2(y - 1.0 - math.cos(phi), x + math.sin(phi)) + math.atan2(2.0, u))
    v = wrap_angle(t - phi)
    return (t, u, v) if t >= -_SLACK and v >= -_SLACK else None


def _left_right_left(x, y, phi):
    xi, eta = x - math.sin(phi), y - 1.0 + math.cos(phi)
    rho = math.hypot(xi, eta)
    if rho > 4.0:
        return None
    u = -2.0 * math.asin(0.25 * rho)
    t = wrap_angle(math.atan2(eta, xi) + 0.5 * u + math.pi)
    v = wrap_angle(phi - t + u)
    return (t, u, v) if t >= -_SLACK and u <= _SLACK else None


def _tau_omega(u, v, xi, eta, phi):
    delta = wrap_angle(u - v)
    a = math.sin(u) - math.sin(delta)
    b = math.cos(u) - math.cos(delta) - 1.0
    t1 = math.atan2(eta * a - xi * b, xi * a + eta * b)
    t2 = 2.0 * (math.cos(delta) - math.cos(v) - math.cos(u)) + 3.0
    tau = wrap_angle(t1 + math.pi) if t2 < 0.0 else wrap_angle(t1)
    return tau, wrap_angle(tau - u + v - phi)


def _left_right_left_right_shrinking(x, y, phi):
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho = 0.25 * (2.0 + math.hypot(xi, eta))
    if rho > 1.0:
        return None
    u = math.acos(rho)
    t, v = _tau_omega(u, -u, xi, eta, phi)
    return (t, u, -u, v) if t >= -_SLACK and v <= _SLACK else None


def _left_right_left_right_equal(x, y, phi):
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho = (20.0 - xi * xi - eta * eta) / 16.0
    if not 0.0 <= rho <= 1.0:
        return None
    u = -math.acos(rho)
    if u < -HALF_PI:
        return None
    t, v = _tau_omega(u, u, xi, eta, phi)
    return (t, u, u, v) if t >= -_SLACK and v >= -_SLACK else None


def _left_right_straight_left(x, y, phi):
    xi, eta = x - math.sin(phi), y - 1.0 + math.cos(phi)
    rho = math.hypot(xi, eta)
    if rho < 2.0:
        return None
    r = math.sqrt(rho * rho - 4.0)
    u = 2.0 - r
    t = wrap_angle(math.atan2(eta, xi) + math.atan2(r, -2.0))
    v = wrap_angle(phi - HALF_PI - t)
    return (t, -HALF_PI, u, v) if t >= -_SLACK and u <= _SLACK and v <= _SLACK else None


def _left_right_straight_right(x, y, phi):
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho = math.hypot(xi, eta)
    if rho < 2.0:
        return None
    t = math.atan2(xi, -eta)
    u = 2.0 - rho
    v = wrap_angle(t + HALF_PI - phi)
    return (t, -HALF_PI, u, v) if t >= -_SLACK and u <= _SLACK and v <= _SLACK else None


def _left_right_straight_left_right(x, y, phi):
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho = math.hypot(xi, eta)
    if rho < 2.0:
        return None
    u = 4.0 - math.sqrt(rho * rho - 4.0)
    if u > _SLACK:
        return None
    t = wrap_angle(math.atan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta))
    v = wrap_angle(t - phi)
    return (t, -HALF_PI, u, -HALF_PI, v) if t >= -_SLACK and v >= -_SLACK else None


# Each base word with its steering, and whether reading it backwards gives new words.
_WORDS = (
    (_left_straight_left, (LEFT, STRAIGHT, LEFT), False),
    (_left_straight_right, (LEFT, STRAIGHT, RIGHT), False),
    (_left_right_left, (LEFT, RIGHT, LEFT), True),
    (_left_right_left_right_shrinking, (LEFT, RIGHT, LEFT, RIGHT), False),
    (_left_right_left_right_equal, (LEFT, RIGHT, LEFT, RIGHT), False),
    (_left_right_straight_left, (LEFT, RIGHT, STRAIGHT, LEFT), True),
    (_left_right_straight_right, (LEFT, RIGHT, STRAIGHT, RIGHT), True),
    (_left_right_straight_left_right, (LEFT, RIGHT, STRAIGHT, LEFT, RIGHT), False),
)


def _mirrors(x, y, phi):
    """Return the goal seen in time reversal and reflection, with the signs that undo them."""
    return ((x, y, phi, 1.0, 1), (-x, y, -phi, -1.0, 1),
            (x, -y, -phi, 1.0, -1), (-x, -y, phi, -1.0, -1))


def shortest_path(x: float, y: float, phi: float, first_direction: int = 0,
                  first_turn: int = 0) -> tuple:
    """
    Return the shortest path from the origin facing +x to (x, y, phi), all in radii.

    A tuple of Segments; their absolute lengths sum to the path length. With first_direction
    +1 or -1, only paths that set off forwards or backwards count; with first_turn +1 or -1,
    only those whose heading first turns that way (counterclockwise, clockwise) or not at all
    (empty if none does).
    """
    best, best_length = (), math.inf
    backwards = (x * math.cos(phi) + y * math.sin(phi), x * math.sin(phi) - y * math.cos(phi))
    for word, steering, reversible in _WORDS:
        goals = [(x, y, False)] + ([(*backwards, True)] if reversible else [])
        for gx, gy, reverse in goals:
            for mx, my, mphi, sign, turn in _mirrors(gx, gy, phi):
                lengths = word(mx, my, mphi)
                if lengths is None:
                    continue
                total = sum(abs(length) for length in lengths)
                if total < best_length:
                    pieces = [Segment(turn * steer, sign * length)
                              for steer, length in zip(steering, lengths)]
                    if reverse:
                        pieces.reverse()
                    if first_direction and _sets_off(pieces) not in (0, first_direction):
                        continue
                    if first_turn and _first_turn(pieces) not in (0, first_turn):
                        continue
                    best, best_length = tuple(pieces), total
    return best


def _sets_off(segments):
    """Return +1 or -1 for the direction of the first segment that moves, 0 if none does."""
    for segment in segments:
        if abs(segment.length) > _SLACK:
            return 1 if segment.length > 0.0 else -1
    return 0


def _first_turn(segments):
    """Return the sign of the heading's first change (+1 counterclockwise), 0 if straight."""
    for segment in segments:
        if abs(segment.length) > _SLACK:
            return segment.steering * (1 if segment.length > 0.0 else -1)
    return 0


def path_length(segments: Sequence[Segment]) -> float:
    """Length of a path in the unit of its segments."""
    return sum(abs(segment.length) for segment in segments)


def advance(pose: tuple, segment: Segment, distance: float, radius: float) -> tuple:
    """
    Pose after driving the first distance metres (unsigned) of segment from pose.

    The segment's length is in radii; the distance is capped at its end.
    """
    x, y, theta = pose
    travelled = math.copysign(min(distance / radius, abs(segment.length)), segment.length)
    if segment.steering == STRAIGHT:
        return (x + travelled * radius * math.cos(theta),
                y + travelled * radius * math.sin(theta), theta)
    turn = segment.steering * travelled
    chord = 2.0 * radius * math.sin(0.5 * turn) * segment.steering
    middle = theta + 0.5 * turn
    return x + chord * math.cos(middle), y + chord * math.sin(middle), theta + turn


def relative_goal(start: tuple, goal: tuple, radius: float) -> tuple:
    """Return goal in the start's frame, in radii: the argument of shortest_path."""
    dx, dy = goal[0] - start[0], goal[1] - start[1]
    cos_t, sin_t = math.cos(start[2]), math.sin(start[2])
    return ((cos_t * dx + sin_t * dy) / radius, (-sin_t * dx + cos_t * dy) / radius,
            wrap_angle(goal[2] - start[2]))
