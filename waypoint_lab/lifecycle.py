"""
The lab's run, from the first pose to FINISHED or ABORTED, for any control law. No ROS here.

A run starts at the first pose the controller answers (STARTED), reports each waypoint whose
goal set the pose enters (WAYPOINT n; several at once if one pose is in several in turn) and
ends FINISHED after the last. It ends ABORTED when there is no progress towards the current
waypoint for stall_timeout seconds of odometry time (an unreachable goal: a wall in the way,
a robot pushing against it), when the pose jumps further than the robot can be driven (a
teleport, a reset of the simulation), when odometry time goes back (a restarted simulator), or
when the law gives a command that is no number. In between, the law is asked for a command
once per control period of odometry time and the command is held in between, so the commands
depend on the poses alone and a simulator in lockstep can count the answers.

A control law (ControlLaw) is anything with aim(pose, index), told that waypoint index of the
course is the goal from pose on, and command(pose, dt) -> (linear m/s, angular rad/s) for the
next dt seconds. A law that plans (PlanningLaw) also has reachable: False once it finds that no
path reaches the goal aimed at; the run then reports UNREACHABLE n and goes on to the next goal
(the planning coursework's rule: a goal given up is said so, not pushed to a stall). A law that
follows routes of its own (RoutingLaw) has remaining(pose): the distance still to go along its
route, which the stall watch then measures progress by (a route round a wall leads away from
the goal for a while), afresh each time its count of plans changes. A law that explores
(ExploringLaw) has exploring: while true, no goal counts as reached (an explorer crosses goal
sets on its way). Laws: the lab's PID answer (waypoint_controller), a learned policy
(policy_controller), a student's own (FunctionLaw wraps a plain function), the courseworks'
planner (coursework_answers). The runner node (runner.py) feeds this from ROS; tests and tools
feed it poses directly.
"""

from collections.abc import Callable, Sequence
from dataclasses import dataclass
import math
from typing import Protocol, runtime_checkable

from simple_robot_control.pose import wrap_angle
from simple_robot_control.validation import shorten
from waypoint_lab.course import goal_error, in_goal_set
from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED,
                                MAX_LINEAR_SPEED)
from waypoint_lab.status import aborted, finished, started, unreachable, waypoint_reached
from waypoint_lab.waypoints import Waypoint

Pose = tuple[float, float, float]
STOP = (0.0, 0.0)
# Slack on top of twice the speed limits before a pose counts as a jump: drift, rounding, a
# simulator's own clamping.
JUMP_DISTANCE = 0.1
JUMP_ANGLE = 0.2


@runtime_checkable
class ControlLaw(Protocol):
    """What a controller of the lab supplies: a command from a pose, towards a waypoint."""

    def aim(self, pose: Pose, index: int) -> None:
        """Take waypoint index of the course as the goal, from pose."""

    def command(self, pose: Pose, dt: float) -> tuple[float, float]:
        """Return (linear m/s, angular rad/s) to hold for the next dt seconds."""


@runtime_checkable
class PlanningLaw(ControlLaw, Protocol):
    """A law that plans: it may find that no path reaches the goal aimed at."""

    # False once no path reaches the goal aimed at.
    reachable: bool


@runtime_checkable
class RoutingLaw(ControlLaw, Protocol):
    """A law that follows routes of its own: progress is the way left along the route."""

    # How many routes the law has planned: a new one is progress measured afresh.
    plans: int

    def remaining(self, pose: Pose) -> float:
        """Return the distance still to go along the route from pose, in metres."""


@runtime_checkable
class ExploringLaw(ControlLaw, Protocol):
    """A law that explores before it drives the goals: none counts as reached meanwhile."""

    exploring: bool


class FunctionLaw:
    """A plain function law(pose, waypoint, dt) -> (linear, angular) as a control law."""

    def __init__(self, waypoints: Sequence[Waypoint],
                 law: Callable[[Pose, Waypoint, float], tuple[float, float]]):
        self._waypoints, self._law, self._goal = list(waypoints), law, None

    def aim(self, pose: Pose, index: int) -> None:
        self._goal = self._waypoints[index]

    def command(self, pose: Pose, dt: float) -> tuple[float, float]:
        return self._law(pose, self._goal, dt)


@dataclass(frozen=True)
class Outcome:
    """
    What one pose led to: statuses to report, waypoints reached, the command, the end.

    command is None where the held one stands; exit_code is set once the run ended (0
    FINISHED, 1 ABORTED), with problem saying why it was aborted.
    """

    statuses: tuple[str, ...] = ()
    reached: tuple[int, ...] = ()
    command: tuple[float, float] | None = None
    exit_code: int | None = None
    problem: str = ''


class StallDetector:
    """
    Reports a stall when neither distance nor heading error has improved for a while.

    An improvement must beat the best value so far by a margin (1 cm, 1 degree), so a robot
    pressed against a wall, creeping by numerical noise, still counts as stalled.
    """

    def __init__(self, timeout: float, distance_margin: float = 0.01,
                 angle_margin: float = math.radians(1.0)):
        if not timeout > 0.0:
            raise ValueError(f'stall timeout must be positive, got {timeout}')
        self.timeout = timeout
        self._margins = (distance_margin, angle_margin)
        self.restart(0.0)

    def restart(self, now: float) -> None:
        """Start watching a new waypoint at time now (seconds)."""
        self._best = (math.inf, math.inf)
        self._last_progress = now

    def stalled(self, now: float, distance: float, angle_error: float) -> bool:
        """Record the errors at time now; return True once progress stopped for timeout."""
        improved = (distance < self._best[0] - self._margins[0]
                    or abs(angle_error) < self._best[1] - self._margins[1])
        if improved:
            self._best = (min(distance, self._best[0]), min(abs(angle_error), self._best[1]))
            self._last_progress = now
        return now - self._last_progress > self.timeout


class ControlSchedule:
    """
    Control ticks on a fixed grid of period_ns, driven by odometry stamps.

    A tick falls on the first stamp at or after each grid point, so the mean rate is exactly
    1/period even when the odometry period does not divide the control period (50 Hz odometry,
    20 Hz control: ticks 60, 40, 60, 40 ms apart rather than every 60 ms).
    """

    def __init__(self, period_ns: int):
        if period_ns <= 0:
            raise ValueError(f'control period must be positive, got {period_ns} ns')
        self.period_ns = period_ns
        self._last = None
        self._next = 0

    def due(self, stamp_ns: int) -> int | None:
        """Return the nanoseconds since the last tick if stamp_ns is a tick, else None."""
        if self._last is not None and stamp_ns < self._next:
            return None
        elapsed = self.period_ns if self._last is None else stamp_ns - self._last
        self._last = stamp_ns
        self._next = stamp_ns + self.period_ns - (stamp_ns - self._next) % self.period_ns
        return elapsed


def jump_problem(previous: Pose, pose: Pose, seconds: float, max_linear: float,
                 max_angular: float) -> str | None:
    """Say how pose cannot follow previous within seconds at these limits, or return None."""
    distance = math.hypot(pose[0] - previous[0], pose[1] - previous[1])
    turn = abs(wrap_angle(pose[2] - previous[2]))
    seconds = max(seconds, 0.0)
    if distance <= JUMP_DISTANCE + 2.0 * max_linear * seconds and (
            turn <= JUMP_ANGLE + 2.0 * max_angular * seconds):
        return None
    before = ', '.join(f'{value:.3f}' for value in (*previous[:2], math.degrees(previous[2])))
    after = ', '.join(f'{value:.3f}' for value in (*pose[:2], math.degrees(pose[2])))
    return (f'the robot moved from ({before}) to ({after}) in {seconds:.3f} s, {distance:.3g} m '
            f'and {math.degrees(turn):.3g} deg, faster than it is driven: it was moved (a '
            'teleport, or a reset of the simulation)')


@dataclass(frozen=True)
class RunRules:
    """How a run is judged and paced: the goal set, the speed limits, the stall, the rate."""

    distance_tolerance: float = DISTANCE_TOLERANCE
    angle_tolerance: float = ANGLE_TOLERANCE
    max_linear_speed: float = MAX_LINEAR_SPEED
    max_angular_speed: float = MAX_ANGULAR_SPEED
    stall_timeout: float = 10.0
    control_period_ns: int = 50_000_000


class RunLifecycle:
    """One run of a course by a control law: feed it every pose with its stamp (observe)."""

    def __init__(self, waypoints: Sequence[Waypoint], law: ControlLaw,
                 rules: RunRules = RunRules()):
        if not waypoints:
            raise ValueError('a course needs at least one waypoint')
        self.waypoints = list(waypoints)
        self.law = law
        # What more than commands the law gives, known once: its plans, its exploring.
        self._planning = law if isinstance(law, PlanningLaw) else None
        self._routing = law if isinstance(law, RoutingLaw) else None
        self._exploring = law if isinstance(law, ExploringLaw) else None
        self.rules = rules
        self.next_index = 0
        self.exit_code = None
        self._stall = StallDetector(rules.stall_timeout)
        self._schedule = ControlSchedule(rules.control_period_ns)
        self._stamp = self._pose = None
        self._retuned = None
        self._plans = None

    @property
    def started(self) -> bool:
        return self._stamp is not None

    def retune(self, rules: RunRules, then: Callable[[], None] | None = None) -> None:
        """
        Take new tolerances and limits at the next control tick, then call then().

        Tuned values take effect together, at a tick (then() retunes the law); the control
        rate stays as it was.
        """
        self._retuned = (rules, then)

    def observe(self, stamp_ns: int, pose: Pose) -> Outcome:
        """Take the pose at odometry time stamp_ns (a stamp seen before changes nothing)."""
        if self.exit_code is not None or stamp_ns == self._stamp:
            return Outcome()
        if self._stamp is not None and stamp_ns < self._stamp:
            return self.abort(pose, f'odometry time went back from {self._stamp * 1e-9:.3f} s '
                              f'to {stamp_ns * 1e-9:.3f} s: the simulator restarted')
        if self._pose is not None:
            rules = self.rules
            jump = jump_problem(self._pose, pose, (stamp_ns - self._stamp) * 1e-9,
                                rules.max_linear_speed, rules.max_angular_speed)
            if jump is not None:
                return self.abort(pose, jump)
        first = self._stamp is None
        self._stamp, self._pose = stamp_ns, pose
        now = stamp_ns * 1e-9
        statuses = [started(pose)] if first else []
        # An exploring law passes through goal sets on its way: none counts until it is done.
        exploring = self._exploring is not None and self._exploring.exploring
        reached = () if exploring else self._advance(pose)
        statuses += [waypoint_reached(index + 1, pose) for index in reached]
        if (first or reached) and self.next_index < len(self.waypoints):
            self._aim(pose, now)
        statuses += self._give_up_unreachable(pose, now)
        if self.next_index == len(self.waypoints):
            self.exit_code = 0
            return Outcome((*statuses, finished()), reached, STOP, 0)
        goal = self.waypoints[self.next_index]
        distance, heading = goal_error(*pose, goal.x, goal.y, goal.theta)
        if self._routing is not None:
            distance = self._routing.remaining(pose)
            if self._routing.plans != self._plans:
                # A new plan (a wall found across the old one) is progress measured afresh.
                self._plans = self._routing.plans
                self._stall.restart(now)
        if self._stall.stalled(now, distance, heading):
            ending = self.abort(pose, (
                f'waypoint {self.next_index + 1} ({goal.x:g}, {goal.y:g}, '
                f'{math.degrees(goal.theta):g} deg) unreachable: no progress for '
                f'{self._stall.timeout:g} s, still {distance:.3g} m away'))
            return Outcome((*statuses, *ending.statuses), reached, STOP, 1, ending.problem)
        elapsed = self._schedule.due(stamp_ns)
        if elapsed is None:
            return Outcome(tuple(statuses), reached)
        return self._command(pose, elapsed * 1e-9, tuple(statuses), reached)

    def abort(self, pose: Pose | None, problem: str) -> Outcome:
        """End the run ABORTED at the current waypoint (the robot gone, the world changed)."""
        self.exit_code = 1
        statuses = (aborted(self.next_index + 1, pose),) if pose is not None else ()
        return Outcome(statuses, (), STOP, 1, problem)

    def _aim(self, pose, now):
        self._stall.restart(now)
        self.law.aim(pose, self.next_index)

    def _give_up_unreachable(self, pose, now):
        """Go past every goal the law says no path reaches; return their UNREACHABLE statuses."""
        statuses = []
        while (self.next_index < len(self.waypoints) and self._planning is not None
               and not self._planning.reachable):
            self.next_index += 1
            statuses.append(unreachable(self.next_index, pose))
            if self.next_index < len(self.waypoints):
                self._aim(pose, now)
        return statuses

    def _advance(self, pose):
        """Go past every waypoint whose goal set holds pose; return their indices."""
        reached = []
        rules = self.rules
        while self.next_index < len(self.waypoints) and in_goal_set(
                pose, self.waypoints[self.next_index], rules.distance_tolerance,
                rules.angle_tolerance):
            reached.append(self.next_index)
            self.next_index += 1
        return tuple(reached)

    def _command(self, pose, dt, statuses, reached):
        """Ask the law; hold its command within the limits, or end the run if it is no number."""
        if self._retuned is not None:
            self.rules, then = self._retuned
            self._retuned = None
            if then is not None:
                then()
        answer = self.law.command(pose, dt)
        try:
            linear, angular = (float(value) for value in answer)
        except (TypeError, ValueError):
            linear = angular = math.nan
        if not (math.isfinite(linear) and math.isfinite(angular)):
            ending = self.abort(pose, f'the control law answered {shorten(repr(answer), 80)}, '
                                'not (linear, angular) as two finite numbers')
            return Outcome(statuses + ending.statuses, reached, STOP, 1, ending.problem)
        rules = self.rules
        return Outcome(statuses, reached, (_clamp(linear, rules.max_linear_speed),
                                           _clamp(angular, rules.max_angular_speed)))


def _clamp(value, limit):
    return max(-limit, min(limit, value))
