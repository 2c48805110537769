"""
Simple reference paths between two poses for a unicycle with speed and turn-rate limits.

A yardstick for the benchmarks, not used by the controller.

Candidates are the six Dubins words (arcs at full turn rate joined by straight lines) at a few
turning radii, and rotate-straight-rotate, each driven forward or backward. An arc takes
angle/omega whatever its radius (a tighter arc is simply driven slower), so offering tighter
radii never makes a turn slower.
A segment is (turn, length): turn is +1 (left arc), -1 (right arc), 0 (straight) or +-2
(rotation in place); length is radians for arcs and rotations and metres for straights.
"""

from dataclasses import dataclass
import math

TWO_PI = 2.0 * math.pi
LEFT, RIGHT, STRAIGHT, SPIN_LEFT, SPIN_RIGHT = 1, -1, 0, 2, -2
SPINS = (SPIN_LEFT, SPIN_RIGHT)


@dataclass(frozen=True)
class Path:
    """A path from a start pose: segments, arc radius and travel direction."""

    name: str
    segments: tuple
    radius: float
    backward: bool

    def duration(self, max_speed, turn_rate):
        """Seconds to drive the path: straights at max_speed, arcs and rotations at turn_rate."""
        return sum(length / (max_speed if turn == STRAIGHT else turn_rate)
                   for turn, length in self.segments)


def _mod(angle):
    return angle % TWO_PI


def _dubins_words(d, alpha, beta):
    """
    Yield (name, segments) for each feasible Dubins word in normalised form.

    d is the distance over the turning radius; alpha and beta are the start and goal headings
    measured from the line joining the points.
    """
    sa, sb, ca, cb = math.sin(alpha), math.sin(beta), math.cos(alpha), math.cos(beta)
    cab = math.cos(alpha - beta)
    squared = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb)
    if squared >= 0.0:
        angle = math.atan2(cb - ca, d + sa - sb)
        yield 'LSL', ((LEFT, _mod(angle - alpha)), (STRAIGHT, math.sqrt(squared)),
                      (LEFT, _mod(beta - angle)))
    squared = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa)
    if squared >= 0.0:
        angle = math.atan2(ca - cb, d - sa + sb)
        yield 'RSR', ((RIGHT, _mod(alpha - angle)), (STRAIGHT, math.sqrt(squared)),
                      (RIGHT, _mod(angle - beta)))
    squared = -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb)
    if squared >= 0.0:
        straight = math.sqrt(squared)
        angle = math.atan2(-ca - cb, d + sa + sb) - math.atan2(-2.0, straight)
        yield 'LSR', ((LEFT, _mod(angle - alpha)), (STRAIGHT, straight),
                      (RIGHT, _mod(angle - beta)))
    squared = d * d - 2.0 + 2.0 * cab - 2.0 * d * (sa + sb)
    if squared >= 0.0:
        straight = math.sqrt(squared)
        angle = math.atan2(ca + cb, d - sa - sb) - math.atan2(2.0, straight)
        yield 'RSL', ((RIGHT, _mod(alpha - angle)), (STRAIGHT, straight),
                      (LEFT, _mod(beta - angle)))
    cosine = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sa - sb)) / 8.0
    if abs(cosine) <= 1.0:
        middle = _mod(TWO_PI - math.acos(cosine))
        first = _mod(alpha - math.atan2(ca - cb, d - sa + sb) + middle / 2.0)
        yield 'RLR', ((RIGHT, first), (LEFT, middle), (RIGHT, _mod(alpha - beta - first + middle)))
    cosine = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sb - sa)) / 8.0
    if abs(cosine) <= 1.0:
        middle = _mod(TWO_PI - math.acos(cosine))
        first = _mod(-alpha - math.atan2(ca - cb, d + sa - sb) + middle / 2.0)
        yield 'LRL', ((LEFT, first), (RIGHT, middle), (LEFT, _mod(beta - alpha - first + middle)))


def _wrap(angle):
    return math.remainder(angle, TWO_PI)


def candidate_paths(start, goal, radii):
    """Return every candidate Path from start to goal, poses given as (x, y, theta)."""
    dx, dy = goal[0] - start[0], goal[1] - start[1]
    distance = math.hypot(dx, dy)
    line = math.atan2(dy, dx) if distance > 0.0 else start[2]
    paths = []
    for backward in (False, True):
        flip = math.pi if backward else 0.0
        first_turn = _wrap(line + flip - start[2])
        last_turn = _wrap(goal[2] - line - flip)
        paths.append(Path('rotate-straight-rotate', (
            (SPIN_LEFT if first_turn >= 0.0 else SPIN_RIGHT, abs(first_turn)),
            (STRAIGHT, distance),
            (SPIN_LEFT if last_turn >= 0.0 else SPIN_RIGHT, abs(last_turn))), 0.0, backward))
        alpha = _mod(start[2] + flip - line)
        beta = _mod(goal[2] + flip - line)
        for radius in radii:
            for name, segments in _dubins_words(distance / radius, alpha, beta):
                segments = tuple((turn, length * radius if turn == STRAIGHT else length)
                                 for turn, length in segments)
                paths.append(Path(name, segments, radius, backward))
    return paths


def follow(start, path, duration, max_speed, turn_rate):
    """
    Return the pose after following path for duration seconds (or to its end), and metres.

    The metres are those travelled on the way. Straights run at max_speed, arcs and rotations
    at turn_rate; the tests integrate paths with this to check that each reaches its goal.
    """
    x, y, theta = start
    remaining = duration
    travelled = 0.0
    flip = math.pi if path.backward else 0.0
    for turn, length in path.segments:
        rate = max_speed if turn == STRAIGHT else turn_rate
        step = min(length, remaining * rate)
        if turn in SPINS:
            theta += math.copysign(step, turn)
        elif turn == STRAIGHT:
            x += step * math.cos(theta + flip)
            y += step * math.sin(theta + flip)
            travelled += step
        else:
            travel = theta + flip
            x += path.radius * turn * (math.sin(travel + turn * step) - math.sin(travel))
            y -= path.radius * turn * (math.cos(travel + turn * step) - math.cos(travel))
            theta += turn * step
            travelled += path.radius * step
        remaining -= step / rate
        if remaining <= 0.0:
            break
    return (x, y, theta), travelled
