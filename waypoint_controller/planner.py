"""
Time-optimal plans to a waypoint's goal set. Pure Python, no ROS.

For this robot (|v| <= V, |omega| <= W, no acceleration limit) the fastest way to a pose is
one of two families: a Reeds-Shepp path at radius V / W driven at full speed (cusps allowed),
or, when the position is already close, turning at full rate all the way while the speed
nudges the position (TurnPlan). The goal is a set (within distance_tolerance, heading within
angle_tolerance), so the planner tries end poses on and inside its edge and keeps the one
that is quickest to reach and to leave towards the next waypoint.
"""

from collections.abc import Callable
from dataclasses import dataclass
import math

from simple_robot_control.pose import wrap_angle
from waypoint_controller.reeds_shepp import advance, path_length, relative_goal, shortest_path

# End poses are aimed this far inside the goal set (fractions of the tolerances), so that the
# pose reached at a control step after the plan's end still lies in it.
DISTANCE_MARGIN = 0.1
ANGLE_MARGIN = 0.2
RING_DIRECTIONS = 8
# When walls veto every end pose of that ring, a denser ring is tried.
WIDE_RING_DIRECTIONS = 24
# Seconds a plan may lose to keep the robot's direction of travel and of turning.
DIRECTION_HYSTERESIS = 0.3
# Only the quickest end poses of the current leg are judged by the leg after it.
LOOKAHEAD_CANDIDATES = 4
NEXT_RING_DIRECTIONS = 4


@dataclass(frozen=True)
class Limits:
    """Speed and turn-rate limits and the goal set's tolerances, SI units and radians."""

    speed: float
    rate: float
    distance: float
    angle: float

    @property
    def radius(self) -> float:
        return self.speed / self.rate


class ReedsSheppPlan:
    """A Reeds-Shepp path from start, driven at full speed."""

    def __init__(self, start, segments, limits: Limits):
        self.start, self.segments, self.limits = start, segments, limits
        self.duration = path_length(segments) / limits.rate

    def pose_at(self, time: float) -> tuple:
        """Pose after time seconds along the plan (the end pose from its duration on)."""
        radius = self.limits.radius
        remaining = max(0.0, time) * self.limits.speed
        pose = self.start
        for segment in self.segments:
            if remaining <= 0.0:
                break
            pose = advance(pose, segment, remaining, radius)
            remaining -= abs(segment.length) * radius
        return pose


class TurnPlan:
    """
    Turn at full rate by angle (signed) while driving v(t) = w . heading(t).

    The speed profile is the least-effort one that moves the position by the wanted offset in
    the time of the turn; it is feasible when |w| <= V.
    """

    def __init__(self, start, angle: float, offset, limits: Limits):
        self.start, self.angle, self.limits = start, angle, limits
        self.duration = abs(angle) / limits.rate
        self._sign = math.copysign(1.0, angle)
        gram = self._gram(self.duration)
        determinant = gram[0] * gram[2] - gram[1] * gram[1]
        if math.hypot(*offset) < 1e-12:
            self.weights = (0.0, 0.0)
        elif determinant <= 1e-12:
            self.weights = (math.inf, math.inf)
        else:
            self.weights = ((gram[2] * offset[0] - gram[1] * offset[1]) / determinant,
                            (gram[0] * offset[1] - gram[1] * offset[0]) / determinant)

    @property
    def feasible(self) -> bool:
        return math.hypot(*self.weights) <= self.limits.speed * (1.0 + 1e-9)

    def _gram(self, time):
        """Integral of heading(t) heading(t)^T over [0, time]: (xx, xy, yy)."""
        if time <= 0.0:
            return 0.0, 0.0, 0.0
        theta0 = self.start[2]
        theta = theta0 + self._sign * self.limits.rate * time
        scale = 4.0 * self._sign * self.limits.rate
        double_sin = (math.sin(2.0 * theta) - math.sin(2.0 * theta0)) / scale
        double_cos = (math.cos(2.0 * theta) - math.cos(2.0 * theta0)) / scale
        return 0.5 * time + double_sin, -double_cos, 0.5 * time - double_sin

    def pose_at(self, time: float) -> tuple:
        time = min(max(0.0, time), self.duration)
        xx, xy, yy = self._gram(time)
        wx, wy = self.weights
        return (self.start[0] + xx * wx + xy * wy, self.start[1] + xy * wx + yy * wy,
                self.start[2] + self._sign * self.limits.rate * time)


# What the planner gives: either kind answers duration and pose_at(time).
Plan = ReedsSheppPlan | TurnPlan


def fastest_plan(start: tuple, target: tuple, limits: Limits, direction: int = 0,
                 turn: int = 0) -> Plan:
    """
    Return the quicker of the Reeds-Shepp path and the feasible full-rate turns to target.

    With direction +1 or -1 (forwards, backwards) and turn +1 or -1 (counterclockwise,
    clockwise), a path setting off that way is kept unless another is quicker by more than
    DIRECTION_HYSTERESIS: between two near-equal paths, the robot does not flip. (Where two
    paths that first turn opposite ways are equally short, each side of the boundary plans
    to turn away from it; with commands that land late the robot would cross it every
    period, planning again each time, and never go either way.)
    """
    relative = relative_goal(start, target, limits.radius)
    best = ReedsSheppPlan(start, shortest_path(*relative), limits)
    if direction or turn:
        steady = ReedsSheppPlan(start, shortest_path(*relative, first_direction=direction,
                                                     first_turn=turn), limits)
        if steady.segments and steady.duration <= best.duration + DIRECTION_HYSTERESIS:
            best = steady
    offset = (target[0] - start[0], target[1] - start[1])
    if math.hypot(*offset) > 2.0 * limits.distance:
        return best
    turn = wrap_angle(target[2] - start[2])
    for angle in (turn, turn - math.copysign(2.0 * math.pi, turn)):
        if abs(angle) / limits.rate <= best.duration + 1e-9:
            plan = TurnPlan(start, angle, offset, limits)
            if plan.feasible:
                best = plan
    return best


def goal_set_poses(waypoint: tuple, limits: Limits, directions: int = RING_DIRECTIONS
                   ) -> list[tuple]:
    """
    Return end poses to try: a ring just inside the goal set's edge, and its centre.

    Ring poses face either end of the heading window, the centre also the goal heading.
    """
    radius = limits.distance * (1.0 - DISTANCE_MARGIN)
    spread = limits.angle * (1.0 - ANGLE_MARGIN)
    positions = [(waypoint[0], waypoint[1])] + [
        (waypoint[0] + radius * math.cos(2.0 * math.pi * index / directions),
         waypoint[1] + radius * math.sin(2.0 * math.pi * index / directions))
        for index in range(directions)]
    centre, ring = positions[0], positions[1:]
    return ([(*centre, waypoint[2] + offset) for offset in (-spread, 0.0, spread)]
            + [(x, y, waypoint[2] + offset) for x, y in ring for offset in (-spread, spread)])


def plan_poses(plan: Plan, spacing: float, horizon: float = math.inf) -> list[tuple]:
    """
    Return poses along a plan, at most spacing metres apart at full speed, ends included.

    Only the first horizon seconds of the plan are sampled.
    """
    duration = min(plan.duration, horizon)
    count = max(1, math.ceil(duration * plan.limits.speed / spacing))
    return [plan.pose_at(duration * index / count) for index in range(count + 1)]


def _time_to_set(start, waypoint, limits):
    """Estimate the quickest time from start into waypoint's goal set, from a few of its poses."""
    return min(fastest_plan(start, target, limits).duration
               for target in goal_set_poses(waypoint, limits, NEXT_RING_DIRECTIONS))


def _displacement(plan):
    end = plan.pose_at(plan.duration)
    return math.hypot(end[0] - plan.start[0], end[1] - plan.start[1])


def _candidate_plans(start, waypoint, limits, directions, is_free):
    """
    Return the plans to poses of the goal set that is_free lets pass, quickest first.

    Between plans equally quick (turns on the spot), the one that moves least comes first.
    """
    plans = sorted((fastest_plan(start, target, limits)
                    for target in goal_set_poses(waypoint, limits, directions)),
                   key=lambda plan: (round(plan.duration, 9), _displacement(plan)))
    return plans if is_free is None else [plan for plan in plans if is_free(plan)]


def plan_to_goal_set(start: tuple, waypoint: tuple, limits: Limits,
                     next_waypoint: tuple | None = None,
                     is_free: Callable[[Plan], bool] | None = None) -> Plan | None:
    """
    Return the plan that reaches waypoint's goal set soonest, counting the next leg if given.

    is_free(plan) may veto plans (walls); when every candidate is vetoed, None.
    """
    plans = _candidate_plans(start, waypoint, limits, RING_DIRECTIONS, is_free)
    if not plans and is_free is not None:
        plans = _candidate_plans(start, waypoint, limits, WIDE_RING_DIRECTIONS, is_free)
    if not plans:
        return None
    if next_waypoint is None:
        return plans[0]
    return min(plans[:LOOKAHEAD_CANDIDATES],
               key=lambda plan: plan.duration + _time_to_set(plan.pose_at(plan.duration),
                                                             next_waypoint, limits))
