"""
Benchmark the waypoint control law in a plain kinematic loop (a benchmark, not a test).

Random seeded courses of five waypoints are driven with exact arc integration; the goal set is
judged on the true pose after every step. Completion time is compared with the lower bound
LB = sum over legs of max(d'/v_max, dtheta'/omega_max), where d' and dtheta' are the leg's
distance and heading change less the tolerances at both ends. A plain rotate-drive-rotate PID
runs on the same courses for comparison.
"""

import argparse
from dataclasses import dataclass
import math
import sys

import numpy as np
from stdr_lite.core.kinematics import arc_step
from waypoint_controller.control_law import (ControllerConfig, CourseFollower, FollowerStep,
                                             in_goal_set, wrap)
from waypoint_controller.pid import PID
from waypoint_controller.waypoints import Waypoint

LEG_KINDS = ('open', 'behind', 'lateral', 'rotation')
LEG_WEIGHTS = (0.55, 0.15, 0.15, 0.15)


def random_course(rng, waypoint_count=5):
    """Return a start pose and waypoints mixing open legs with the hard kinds."""
    x, y, theta = 0.0, 0.0, rng.uniform(-math.pi, math.pi)
    start = (x, y, theta)
    waypoints = []
    for kind in rng.choice(LEG_KINDS, size=waypoint_count, p=LEG_WEIGHTS):
        if kind == 'open':
            distance, bearing = rng.uniform(0.5, 3.0), rng.uniform(-math.pi, math.pi)
            x, y = x + distance * math.cos(bearing), y + distance * math.sin(bearing)
            theta = rng.uniform(-math.pi, math.pi)
        elif kind == 'behind':
            distance = rng.uniform(0.5, 1.0)
            x, y = x - distance * math.cos(theta), y - distance * math.sin(theta)
            theta = wrap(theta + rng.uniform(-math.pi / 4, math.pi / 4))
        elif kind == 'lateral':
            offset = rng.choice((-1.0, 1.0)) * rng.uniform(0.5, 1.0)
            x, y = x - offset * math.sin(theta), y + offset * math.cos(theta)
        else:
            theta = wrap(theta + rng.choice((-1.0, 1.0)) * rng.uniform(math.pi / 6, math.pi))
        waypoints.append(Waypoint(x, y, theta))
    return start, waypoints


def lower_bound(start, waypoints, config):
    total = 0.0
    previous = start
    for waypoint in waypoints:
        distance = math.hypot(waypoint.x - previous[0], waypoint.y - previous[1])
        turn = abs(wrap(waypoint.theta - previous[2]))
        total += max(max(0.0, distance - 2 * config.distance_tolerance)
                     / config.max_linear_speed,
                     max(0.0, turn - 2 * config.angle_tolerance) / config.max_angular_speed)
        previous = (waypoint.x, waypoint.y, waypoint.theta)
    return total


class RotateDriveRotate:
    """The textbook baseline: turn to face the goal, drive straight, turn to its heading."""

    def __init__(self, waypoints, config):
        self.waypoints, self.config = waypoints, config
        self.next_index = 0
        self._heading = PID(4.0, 0.0, 0.0, config.max_angular_speed)
        self._distance = PID(2.0, 0.0, 0.0, config.max_linear_speed)

    def update(self, pose, dt):
        reached = []
        while (self.next_index < len(self.waypoints)
               and in_goal_set(pose, self.waypoints[self.next_index], self.config)):
            reached.append(self.next_index)
            self.next_index += 1
        if self.next_index == len(self.waypoints):
            return FollowerStep(0.0, 0.0, tuple(reached), True)
        goal = self.waypoints[self.next_index]
        x, y, theta = pose
        distance = math.hypot(goal.x - x, goal.y - y)
        kp = min(4.0, 0.9 / dt)
        if distance <= 0.5 * self.config.distance_tolerance:
            angular = self._heading.update(wrap(goal.theta - theta), dt, kp=kp)
            return FollowerStep(0.0, angular, tuple(reached), False)
        facing_error = wrap(math.atan2(goal.y - y, goal.x - x) - theta)
        angular = self._heading.update(facing_error, dt, kp=kp)
        if abs(facing_error) > math.radians(5.0):
            return FollowerStep(0.0, angular, tuple(reached), False)
        linear = self._distance.update(distance, dt, kp=min(2.0, 0.9 / dt))
        return FollowerStep(linear, angular, tuple(reached), False)


@dataclass
class Run:
    success: bool
    time: float
    path_length: float
    reversals: int


def drive(follower, start, dt, time_limit):
    """Run one course in a plain loop: control, then one exact-arc step of the true pose."""
    pose = start
    path_length, reversals, last_sign, elapsed = 0.0, 0, 0.0, 0.0
    while elapsed <= time_limit:
        step = follower.update(pose, dt)
        if step.finished:
            return Run(True, elapsed, path_length, reversals)
        sign = math.copysign(1.0, step.angular) if abs(step.angular) > 1e-3 else 0.0
        if sign and last_sign and sign != last_sign:
            reversals += 1
        last_sign = sign or last_sign
        x, y, theta = (float(value) for value in arc_step(*pose, step.linear, step.angular, dt))
        path_length += math.hypot(x - pose[0], y - pose[1])
        pose = (x, y, theta)
        elapsed += dt
    return Run(False, elapsed, path_length, reversals)


def evaluate(make_follower, courses, config, dt):
    ratios, stretch, reversals, failures = [], [], [], 0
    for start, waypoints in courses:
        bound = lower_bound(start, waypoints, config)
        run = drive(make_follower(waypoints), start, dt, time_limit=10.0 * bound + 30.0)
        if not run.success:
            failures += 1
            continue
        ratios.append(run.time / bound)
        straight = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(
            [start] + [(w.x, w.y) for w in waypoints], [(w.x, w.y) for w in waypoints]))
        stretch.append(run.path_length / straight)
        reversals.append(run.reversals / len(waypoints))
    return {'success': 1.0 - failures / len(courses),
            'ratio_median': float(np.median(ratios)) if ratios else math.nan,
            'ratio_p90': float(np.percentile(ratios, 90)) if ratios else math.nan,
            'stretch_median': float(np.median(stretch)) if stretch else math.nan,
            'reversals_mean': float(np.mean(reversals)) if reversals else math.nan,
            'reversals_p90': float(np.percentile(reversals, 90)) if reversals else math.nan}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--courses', type=int, default=1000)
    parser.add_argument('--seed', type=int, default=2026)
    parser.add_argument('--dt', type=float, nargs='+', default=[0.05, 0.01, 0.2])
    parser.add_argument('--no-baseline', action='store_true')
    args = parser.parse_args(argv)
    config = ControllerConfig()
    rng = np.random.default_rng(args.seed)
    courses = [random_course(rng) for _ in range(args.courses)]
    contenders = [('waypoint_controller', lambda w: CourseFollower(w, config))]
    if not args.no_baseline:
        contenders.append(('rotate-drive-rotate', lambda w: RotateDriveRotate(w, config)))
    print(f'{args.courses} courses of 5 waypoints, seed {args.seed}, limits '
          f'{config.max_linear_speed} m/s {config.max_angular_speed} rad/s, goal set '
          f'{config.distance_tolerance} m / {math.degrees(config.angle_tolerance):g} deg')
    print(f'{"controller":22} {"dt":>5} {"success":>8} {"T/LB med":>9} {"T/LB p90":>9} '
          f'{"path/line":>9} {"w rev/wp":>9} {"rev p90":>8}')
    for name, make_follower in contenders:
        for dt in args.dt:
            result = evaluate(make_follower, courses, config, dt)
            print(f'{name:22} {dt:5.2f} {result["success"]:8.1%} {result["ratio_median"]:9.3f} '
                  f'{result["ratio_p90"]:9.3f} {result["stretch_median"]:9.3f} '
                  f'{result["reversals_mean"]:9.2f} {result["reversals_p90"]:8.2f}',
                  flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
