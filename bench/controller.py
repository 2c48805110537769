"""
Benchmark the waypoint control law in a plain kinematic loop (a benchmark, not a test).

Random seeded courses of five waypoints (bench/courses.py) are driven with exact arc
integration; the goal set is judged after every step on the pose the controller sees.
Completion time is compared with the time-optimal chain of bench/optimum.py replayed in the
same loop at the same dt (T/opt), and with the simple bound LB = sum over legs of
max(d'/v_max, dtheta'/omega_max), where d' and dtheta' are the leg's distance and heading change
less the tolerances at both ends. The controller also runs at control rates below the step
rate, with drifting odometry and with its commands a control period late. A plain
rotate-drive-rotate PID runs for comparison.
"""

import argparse
import math
import sys
import time

from bench.courses import (drive, LEG_KINDS, Loop, lower_bound, random_course,
                           TYPICAL_DRIFT)
from bench.optimum import course_optimum, ReedsSheppTimes, replay
import numpy as np
from simple_robot_control.pose import wrap_angle as wrap
from waypoint_controller.config import ControllerConfig
from waypoint_controller.control_law import plan_limits, PlannedLaw
from waypoint_controller.pid import PID
from waypoint_controller.planner import plan_to_goal_set


class RotateDriveRotate:
    """The textbook baseline: turn to face the goal, drive straight, turn to its heading."""

    def __init__(self, waypoints, config):
        self.waypoints, self.config = waypoints, config
        self._heading = PID(4.0, 0.0, 0.0, config.max_angular_speed)
        self._distance = PID(2.0, 0.0, 0.0, config.max_linear_speed)
        self._goal = None

    def aim(self, pose, index):
        self._goal = self.waypoints[index]

    def command(self, pose, dt):
        goal = self._goal
        x, y, theta = pose
        distance = math.hypot(goal.x - x, goal.y - y)
        kp = min(4.0, 0.9 / dt)
        if distance <= 0.5 * self.config.distance_tolerance:
            return 0.0, self._heading.update(wrap(goal.theta - theta), dt, kp=kp)
        facing_error = wrap(math.atan2(goal.y - y, goal.x - x) - theta)
        angular = self._heading.update(facing_error, dt, kp=kp)
        if abs(facing_error) > math.radians(5.0):
            return 0.0, angular
        return self._distance.update(distance, dt, kp=min(2.0, 0.9 / dt)), angular


def evaluate(make_law, courses, config, loop, optimum_runs=None):
    """Measure one controller in one loop; T/opt against the replayed optimum's runs."""
    ratios, optimal, stretch, reversals, failures = [], [], [], [], 0
    by_kind = {kind: [] for kind in LEG_KINDS}
    for index, (start, waypoints, kinds) in enumerate(courses):
        run = drive(make_law(waypoints), waypoints, start, loop, config)
        if not run.success:
            failures += 1
            continue
        ratios.append(run.time / lower_bound(start, waypoints, config))
        if optimum_runs is not None:
            reference = optimum_runs[index]
            optimal.append(run.time / reference.time)
            for kind, leg, best in zip(kinds, run.leg_times, reference.leg_times):
                if best > 0.0:
                    by_kind[kind].append(leg / best)
        straight = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(
            [start] + [(w.x, w.y) for w in waypoints], [(w.x, w.y) for w in waypoints]))
        stretch.append(run.path_length / straight)
        reversals.append(run.reversals / len(waypoints))
    return {'success': 1.0 - failures / len(courses), 'lb': _spread(ratios),
            'opt': _spread(optimal), 'stretch': _spread(stretch)[0],
            'reversals': float(np.mean(reversals)) if reversals else math.nan,
            'kinds': {kind: _spread(values)[0] for kind, values in by_kind.items()}}


def _spread(values):
    """(median, p90), nan when empty."""
    if not values:
        return math.nan, math.nan
    return float(np.median(values)), float(np.percentile(values, 90))


def optimum_chains(courses, config):
    """Return the optimum chain of every course (bench/optimum.py): an end pose per waypoint."""
    reeds_shepp = ReedsSheppTimes(config)
    return [course_optimum(start, waypoints, config, reeds_shepp)[2]
            for start, waypoints, _ in courses]


def replayed_optimum(courses, chains, config, dt):
    """Replay every course's optimum chain in the loop at dt."""
    return [replay(start, waypoints, chain, config, dt)
            for (start, waypoints, _), chain in zip(courses, chains)]


HEADER = (f'{"controller":21} {"loop":22} {"success":>7} {"T/opt":>6} {"p90":>6} '
          f'{"T/LB":>6} {"p90":>6} {"path/line":>9} {"w rev/wp":>8}  T/opt by leg kind')


def report(name, label, result):
    kinds = ' '.join(f'{kind} {value:.3f}' for kind, value in result['kinds'].items())
    print(f'{name:21} {label:22} {result["success"]:7.1%} {result["opt"][0]:6.3f} '
          f'{result["opt"][1]:6.3f} {result["lb"][0]:6.3f} {result["lb"][1]:6.3f} '
          f'{result["stretch"]:9.3f} {result["reversals"]:8.2f}  {kinds}', flush=True)


def planning_times(courses, config):
    """Seconds the planner takes at each waypoint switch of the courses (with lookahead)."""
    seconds = []
    for start, waypoints, _ in courses:
        poses = [(w.x, w.y, w.theta) for w in waypoints] + [None]
        pose = start
        for waypoint, following in zip(poses, poses[1:]):
            began = time.perf_counter()
            plan = plan_to_goal_set(pose, waypoint, plan_limits(config), following)
            seconds.append(time.perf_counter() - began)
            pose = plan.pose_at(plan.duration)
    return seconds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--courses', type=int, default=1000)
    parser.add_argument('--seed', type=int, default=2026)
    parser.add_argument('--dt', type=float, nargs='+', default=[0.05, 0.01, 0.2])
    parser.add_argument('--rates', type=float, nargs='*', default=[5.0, 10.0, 20.0, 50.0],
                        help='control rates [Hz] to run against a 100 Hz loop')
    parser.add_argument('--no-baseline', action='store_true')
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    if args.smoke:
        args.courses, args.dt, args.rates = 3, [0.05], [10.0]
    config = ControllerConfig()
    rng = np.random.default_rng(args.seed)
    courses = [random_course(rng) for _ in range(args.courses)]
    print(f'{args.courses} courses of 5 waypoints, seed {args.seed}, limits '
          f'{config.max_linear_speed} m/s {config.max_angular_speed} rad/s, goal set '
          f'{config.distance_tolerance} m / {math.degrees(config.angle_tolerance):g} deg; '
          'T/opt: time / the optimum replayed at the same dt')
    print(HEADER)
    ours = ('waypoint_controller', lambda w: PlannedLaw(w, config))
    contenders = [ours] + ([] if args.no_baseline else [
        ('rotate-drive-rotate', lambda w: RotateDriveRotate(w, config))])
    chains = optimum_chains(courses, config)
    optimum = {}
    for dt in sorted(set(args.dt) | ({0.01} if args.rates else set())):
        optimum[dt] = replayed_optimum(courses, chains, config, dt)
    for name, make_law in contenders:
        for dt in args.dt:
            report(name, f'dt {dt:g}', evaluate(make_law, courses, config, Loop(dt),
                                                optimum[dt]))
    for rate in args.rates:
        loop = Loop(0.01, control_every=round(100.0 / rate))
        report(ours[0], f'dt 0.01, control {rate:g} Hz',
               evaluate(ours[1], courses, config, loop, optimum[0.01]))
    base = 0.05 if 0.05 in optimum else args.dt[0]
    report(ours[0], f'dt {base:g}, drifting odom',
           evaluate(ours[1], courses, config, Loop(base, drift=TYPICAL_DRIFT), optimum[base]))
    report(ours[0], f'dt {base:g}, 1 period late',
           evaluate(ours[1], courses, config, Loop(base, late_by=1), optimum[base]))
    seconds = planning_times(courses, config)
    print(f'planning per waypoint: median {np.median(seconds) * 1e3:.2f} ms, '
          f'p99 {np.percentile(seconds, 99) * 1e3:.2f} ms, max {max(seconds) * 1e3:.2f} ms')
    return 0


if __name__ == '__main__':
    sys.exit(main())
