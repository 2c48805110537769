"""
The tick-off sheet's rules: each check of a course, judged from its recorded run. No ROS here.

A status message is judged against the robot's true path around its date (the sim time at
which it was sent: waypoint_lab/run.py), from LATENCY before (the controller's reaction: the
odometry it acts on is older than the message) to SLACK after (a step's truth and odometry go
out one after the other). A
report passes when in that window the robot stood in the waypoint's goal set, at the pose it
reported (within POSITION_MATCH and HEADING_MATCH: the lab prints poses to a few millimetres).
"""

from dataclasses import dataclass
import math

from lab_grader.simulator_link import SpeedLimits
import numpy as np
from waypoint_lab.course import goal_errors, in_goal_set
from waypoint_lab.rules import WAYPOINTS_TASK
from waypoint_lab.run import Run
from waypoint_lab.status import FINISHED, STARTED, UNREACHABLE, WAYPOINT

LATENCY = 0.5
SLACK = 0.05
POSITION_MATCH = 0.02
HEADING_MATCH = math.radians(1.0)
# After FINISHED the robot must stand still (from SETTLE after it to the end of the run).
SETTLE = 0.5
STILL_DISTANCE = 0.01
STILL_HEADING = math.radians(1.0)
LAST_LINES = 12
# What a program prints when an allocation fails: Python's, C++'s, C's.
OUT_OF_MEMORY = ('MemoryError', 'std::bad_alloc', 'Cannot allocate memory')
FAIR_PLAY = 'fair play'
# A step may carry the robot at most its speed limits (both axes at the linear limit for an
# omni robot), with this much slack for rounding.
SPEED_SLACK = 0.01


@dataclass(frozen=True)
class Check:
    """One line of the tick-off sheet: what was checked, whether it passed, and why."""

    name: str
    passed: bool
    evidence: str


@dataclass(frozen=True)
class ProcessOutcome:
    """How the submission's process ran and ended."""

    start_error: str = ''
    ended_by: str = 'itself'
    exit_code: int | None = 0
    seconds: float = 0.0
    stop_seconds: float = 0.0
    timed_out: bool = False
    last_lines: tuple[str, ...] = ()
    leftovers: tuple[str, ...] = ()


def _degrees(angle):
    return f'{math.degrees(angle):.1f}°'


def _pose_text(pose):
    x, y, theta = pose
    return f'({x:.3f}, {y:.3f}, {_degrees(theta)})'


def _match(run, indices, reported):
    """Return (index, position error, heading error) of the true pose nearest to reported."""
    distance, heading = goal_errors(run.poses[indices], reported)
    best = int(np.argmin(np.maximum(distance / POSITION_MATCH, heading / HEADING_MATCH)))
    return indices[best], float(distance[best]), float(heading[best])


def _honest(distance, heading):
    return distance <= POSITION_MATCH and heading <= HEADING_MATCH


class Judge:
    """Judges one course's run: judge.checks() gives every line of its tick-off sheet."""

    def __init__(self, course, run, outcome, fouls=(), limits=None):
        self.course, self.run, self.outcome = course, run, outcome
        self.fouls, self.limits = tuple(fouls), limits
        self.lab = run.statuses
        self.finished = next((report for report in self.lab
                              if report.status.kind == FINISHED), None)

    def checks(self, task_checks: list[Check] = ()) -> list[Check]:
        """Return the sheet: the lab's checks, then a coursework's own, then the end."""
        checks = [self._started()]
        checks += [self._goal(number) for number in range(1, len(self.course.waypoints) + 1)]
        checks += [self._finished(), self._contact()]
        if self.course.max_time is not None:
            checks.append(self._limit('time', self.time_taken, self.course.max_time, 's'))
        if self.course.max_path_length is not None:
            checks.append(self._limit('path length', self.path_length,
                                      self.course.max_path_length, 'm'))
        checks += task_checks
        fair_play = self._fair_play()
        return checks + [fair_play] * (not fair_play.passed) + [self._ending()]

    @property
    def time_taken(self) -> float | None:
        """Sim seconds from STARTED to FINISHED, or None without both."""
        started = next((r for r in self.lab if r.status.kind == STARTED), None)
        if started is None or self.finished is None:
            return None
        return self.finished.time - started.time

    @property
    def path_length(self) -> float | None:
        """Metres driven from STARTED to FINISHED, or None without both."""
        if self.time_taken is None:
            return None
        return self.run.path_length(self.finished.time - self.time_taken, self.finished.time)

    def _window(self, report):
        return self.run.during(report.time - LATENCY, report.time + SLACK)

    def _why_missing(self):
        """Say why the run ended without a message, when the process tells."""
        outcome = self.outcome
        if outcome.start_error:
            return f': {outcome.start_error}'
        if outcome.timed_out:
            return f' within the time limit of {self.course.time_limit:g} s'
        if outcome.ended_by == 'itself':
            return f' (the program ended after {outcome.seconds:.1f} s, exit code ' \
                   f'{outcome.exit_code})'
        return ''

    def _started(self):
        if not self.run.reports:
            return Check(STARTED, False, f'no message on robot_status{self._why_missing()}')
        first = self.run.reports[0]
        if first.status is None or first.status.kind != STARTED:
            return Check(STARTED, False, f'the first message was {first.text[:60]!r}, not '
                         'STARTED <x> <y> <theta>')
        count = sum(report.status.kind == STARTED for report in self.lab)
        if count > 1:
            return Check(STARTED, False, f'sent {count} times')
        window = self._window(first)
        if not len(window):
            return Check(STARTED, False, 'no true pose recorded around it')
        index, distance, heading = _match(self.run, window, first.status.pose)
        true_pose = _pose_text(self.run.poses[index])
        if not _honest(distance, heading):
            return Check(STARTED, False, f'reported {_pose_text(first.status.pose)}, but the '
                         f'robot was at {true_pose}: {distance * 100:.1f} cm and '
                         f'{_degrees(heading)} off (at most {POSITION_MATCH * 100:g} cm and '
                         f'{_degrees(HEADING_MATCH)})')
        return Check(STARTED, True, f'first, at t = {first.time:.2f} s, with the true start '
                     f'pose {true_pose}')

    def _report_name(self, number):
        """Name the report goal number takes: WAYPOINT n, or either kind where it may plan."""
        if self.course.task == WAYPOINTS_TASK:
            return f'{WAYPOINT} {number}'
        return f'{WAYPOINT} or {UNREACHABLE} {number}'

    def _goal_reports(self, number):
        """Return (position among the statuses, report) of each report that names goal number."""
        return [(position, report) for position, report in enumerate(self.lab)
                if report.status.kind in (WAYPOINT, UNREACHABLE)
                and report.status.number == number]

    def _disorder(self, number, position):
        """Say how goal number's report, at position among the statuses, is out of order."""
        before = self.lab[position - 1].status if position else None
        if number == 1:
            in_order = before is not None and before.kind == STARTED
        else:
            in_order = before is not None and (before.kind, before.number) in (
                (WAYPOINT, number - 1), (UNREACHABLE, number - 1))
        if in_order:
            return ''
        said = 'first' if before is None else f'after {before.kind} {before.number or ""}'
        expected = STARTED if number == 1 else self._report_name(number - 1)
        return f'out of order: sent {said.strip()}, not after {expected}'

    def _goal(self, number):
        """
        Check goal number's report: WAYPOINT n once, in order, in the goal set, honest.

        A course of a coursework that plans (not the lab's) may have the goal reported
        UNREACHABLE n instead, in the same place; whether it truly is, its task's check judges.
        """
        sent = self._goal_reports(number)
        kind = sent[0][1].status.kind if len(sent) == 1 else WAYPOINT
        name = f'{kind} {number}'
        if not sent:
            return Check(name, False, 'never sent (neither WAYPOINT nor UNREACHABLE)'
                         if self.course.task != WAYPOINTS_TASK else 'never sent')
        if len(sent) > 1:
            return Check(name, False, f'sent {len(sent)} times')
        position, report = sent[0]
        disorder = self._disorder(number, position)
        if disorder:
            return Check(name, False, disorder)
        if kind == UNREACHABLE:
            return self._given_up(name, report)
        waypoint = self.course.waypoints[number - 1]
        window = self._window(report)
        if not len(window):
            return Check(name, False, 'no true pose recorded around it')
        course = self.course
        poses = self.run.poses[window]
        inside = window[in_goal_set(poses, waypoint, course.distance_tolerance,
                                    course.angle_tolerance)]
        if not len(inside):
            distance, heading = goal_errors(poses, waypoint)
            nearest = int(np.argmin(np.maximum(distance / self.course.distance_tolerance,
                                               heading / self.course.angle_tolerance)))
            return Check(name, False, f'sent at t = {report.time:.2f} s while the robot was '
                         f'{distance[nearest]:.3f} m and {_degrees(heading[nearest])} from '
                         f'waypoint {number} (goal set: {self.course.distance_tolerance:g} m '
                         f'and {_degrees(self.course.angle_tolerance)})')
        index, error, turn = _match(self.run, inside, report.status.pose)
        if not _honest(error, turn):
            return Check(name, False, f'reported {_pose_text(report.status.pose)}, but the '
                         f'robot was at {_pose_text(self.run.poses[index])}: '
                         f'{error * 100:.1f} cm and {_degrees(turn)} off (at most '
                         f'{POSITION_MATCH * 100:g} cm and {_degrees(HEADING_MATCH)})')
        off, off_heading = (values[0] for values in goal_errors(
            self.run.poses[[index]], waypoint))
        return Check(name, True, f'sent at t = {report.time:.2f} s in the goal set '
                     f'({off:.3f} m, {_degrees(off_heading)} from the waypoint), reporting the '
                     f'true pose within {error * 100:.1f} cm and {_degrees(turn)}')

    def _finished(self):
        if self.finished is None:
            return Check(FINISHED, False, f'never sent{self._why_missing()}')
        position = self.lab.index(self.finished)
        count = len(self.course.waypoints)
        last = self._report_name(count)
        before = self.lab[position - 1].status if position else None
        if before is None or before.kind not in (WAYPOINT, UNREACHABLE) or before.number != count:
            return Check(FINISHED, False, f'sent before {last}')
        last = f'{before.kind} {count}'
        after = self.run.reports[self.run.reports.index(self.finished) + 1:]
        if after:
            return Check(FINISHED, False, f'{len(after)} message(s) after it, the first '
                         f'{after[0].text[:60]!r}')
        still = self.run.during(self.finished.time + SETTLE, math.inf)
        if len(still) < 2:
            return Check(FINISHED, True, f'after {last}, and nothing after it; the simulation '
                         'did not step on after it (lockstep waits for the controller)')
        poses = self.run.poses[still]
        moved, turned = (float(np.max(errors)) for errors in goal_errors(poses, poses[0]))
        held = f'{self.run.times[still[-1]] - self.run.times[still[0]]:.1f} s'
        if moved > STILL_DISTANCE or turned > STILL_HEADING:
            return Check(FINISHED, False, f'the robot did not stop: it moved {moved:.3f} m and '
                         f'turned {_degrees(turned)} in the {held} after it (send a zero '
                         'cmd_vel: the simulator holds the last command, as STDR does)')
        return Check(FINISHED, True, f'after {last}, and nothing after it; the robot then '
                     f'stood still for {held}')

    def _given_up(self, name, report):
        """Check an UNREACHABLE report: never on the lab's courses; elsewhere, honest."""
        if self.course.task == WAYPOINTS_TASK:
            return Check(name, False, f'sent at t = {report.time:.2f} s: every goal of the '
                         "lab is to be reached (UNREACHABLE is the planning coursework's)")
        window = self._window(report)
        if not len(window):
            return Check(name, False, 'no true pose recorded around it')
        index, error, turn = _match(self.run, window, report.status.pose)
        if not _honest(error, turn):
            return Check(name, False, f'reported {_pose_text(report.status.pose)}, but the '
                         f'robot was at {_pose_text(self.run.poses[index])}')
        return Check(name, True, f'given up at t = {report.time:.2f} s at the true pose '
                     f'{_pose_text(self.run.poses[index])} (whether no path reaches it: see '
                     f'the {self.course.task} check)')

    def _contact(self):
        name = 'no wall contact'
        run = self.run
        if not run.stalled_steps:
            span = run.times[-1] - run.times[0] if len(run.times) > 1 else 0.0
            return Check(name, True, f'never pushed against a wall in {span:.1f} s')
        where = run.pose_at(run.first_stall)
        return Check(name, False, f'pushed against a wall for {run.stalled_seconds:.2f} s '
                     f'({run.stalled_steps} steps), first at t = '
                     f'{run.first_stall:.2f} s at {_pose_text(where)}')

    def _fair_play(self):
        """
        Check what the submission did to the run itself (a line that shows only when failed).

        Fouls are what the grader saw while the run went (another publisher on the simulator's
        topics, a flood of statuses, the simulator ended); a true path that jumps faster than
        the robot can move was moved by something other than its commands.
        """
        problems = list(self.fouls)
        jump = undrivable(self.run, self.limits)
        if jump:
            problems.append(jump)
        if problems:
            return Check(FAIR_PLAY, False, '; '.join(problems))
        return Check(FAIR_PLAY, True, 'nothing but the simulator moved the robot or published '
                     'its topics')

    def _limit(self, name, value, limit, unit):
        if value is None:
            return Check(name, False, 'not measured: the course was not finished')
        verdict = 'within' if value <= limit else 'over'
        return Check(name, value <= limit, f'{value:.2f} {unit}, {verdict} the limit of '
                     f'{limit:g} {unit}')

    def _ending(self):
        name = 'ends when asked'
        outcome = self.outcome
        if outcome.start_error:
            return Check(name, False, outcome.start_error)
        lines = ''.join(f'\n    {line}' for line in outcome.last_lines[-LAST_LINES:])
        if outcome.leftovers:
            return Check(name, False, f'left {len(outcome.leftovers)} process(es) running '
                         f'after it ended, killed: {"; ".join(outcome.leftovers)[:200]}')
        if outcome.ended_by == 'itself':
            if outcome.exit_code == 0:
                return Check(name, True, f'exited by itself with exit code 0 after '
                             f'{outcome.seconds:.1f} s')
            memory = ' (it ran out of the memory grade_lab --memory allows)' if any(
                sign in line for line in outcome.last_lines for sign in OUT_OF_MEMORY) else ''
            return Check(name, False, f'crashed after {outcome.seconds:.1f} s: '
                         f'{_exit_text(outcome.exit_code)}{memory}; its last lines:{lines}')
        if outcome.ended_by == 'SIGINT':
            return Check(name, True, f'still running when the course was over; ended on '
                         f'Ctrl-C (SIGINT) in {outcome.stop_seconds:.1f} s')
        return Check(name, False, f'ignored Ctrl-C (SIGINT) for {outcome.stop_seconds:.0f} s: '
                     f'ended only by {outcome.ended_by} (a ROS node must end on SIGINT: '
                     'ros2 launch and Ctrl-C stop it so)')


def _exit_text(code):
    if code is not None and code < 0:
        return f'killed by signal {-code}'
    return f'exit code {code}'


def undrivable(run: Run, limits: SpeedLimits | None) -> str:
    """Say where the true path jumps faster than the speed limits allow, or return ''."""
    if limits is None or len(run.times) < 2:
        return ''
    steps = np.diff(run.times)
    moves = np.diff(run.poses, axis=0)
    moved = np.hypot(moves[:, 0], moves[:, 1])
    turned = np.abs((moves[:, 2] + math.pi) % (2.0 * math.pi) - math.pi)
    reach = math.sqrt(2.0) * limits.linear * steps * (1.0 + SPEED_SLACK) + 1e-6
    turn = limits.angular * steps * (1.0 + SPEED_SLACK) + 1e-6
    jumps = np.flatnonzero((moved > reach) | (turned > turn))
    if not len(jumps):
        return ''
    first = int(jumps[0])
    return (f'the true path is not drivable: the robot went {moved[first]:.3f} m and turned '
            f'{_degrees(turned[first])} in {steps[first]:.3f} s at t = '
            f'{run.times[first + 1]:.2f} s (at most {limits.linear:g} m/s and '
            f'{limits.angular:g} rad/s): something other than its commands moved it')
