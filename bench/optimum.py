"""
The fastest the controller benchmark's courses can be driven (a benchmark, not a test).

For this robot (|v| <= V, |omega| <= W, no acceleration limit) the time-optimal path between
two poses is a full-speed Reeds-Shepp path at radius V / W, or, when the positions are close,
a turn at full rate throughout. Each goal set is sampled on its edge (where the best end pose
lies), inside and at its centre, and per course three figures are printed against LB:

- lower bound: every leg at its best over start and end pose in their goal sets (no real run
  can beat it: the sampling only makes it a little higher than the exact bound);
- chained optimum: the fastest chain of legs through sampled poses, one per goal set
  (feasible, as passing through a waypoint costs nothing without an acceleration limit);
- replayed: that chain driven in the bench loop at dt, the goal judged after every step.

Reeds-Shepp distances come from OMPL (ompl.base.ReedsSheppStateSpace); the replay tracks the
same paths built by waypoint_controller's own closed form, which the tests check against OMPL.
"""

import argparse
import math
import sys

from bench.courses import drive, Loop, lower_bound, random_course
import numpy as np
from ompl import base as ompl_base
from simple_robot_control.pose import wrap_angle
from waypoint_controller.config import ControllerConfig
from waypoint_controller.control_law import plan_limits, PlannedLaw
from waypoint_controller.planner import TurnPlan

EDGE_DIRECTIONS = 16
INNER_DIRECTIONS = 8
# Replayed end poses are moved this much inside the goal set, so that landing on one counts.
REPLAY_INSET = (5e-3, math.radians(0.25))


def goal_set_samples(waypoint, config: ControllerConfig) -> np.ndarray:
    """Poses of a goal set: its edge, a ring halfway in and its centre, at three headings."""
    rings = [(config.distance_tolerance, EDGE_DIRECTIONS),
             (0.5 * config.distance_tolerance, INNER_DIRECTIONS), (0.0, 1)]
    positions = [(waypoint.x + radius * math.cos(2 * math.pi * index / count),
                  waypoint.y + radius * math.sin(2 * math.pi * index / count))
                 for radius, count in rings for index in range(count)]
    headings = (waypoint.theta - config.angle_tolerance, waypoint.theta,
                waypoint.theta + config.angle_tolerance)
    return np.array([(x, y, theta) for x, y in positions for theta in headings])


class ReedsSheppTimes:
    """Full-speed Reeds-Shepp times between poses, from OMPL."""

    def __init__(self, config: ControllerConfig):
        self._space = ompl_base.ReedsSheppStateSpace(
            config.max_linear_speed / config.max_angular_speed)
        self._speed = config.max_linear_speed

    def _states(self, poses):
        states = []
        for x, y, theta in poses:
            state = self._space.allocState()
            state.setXY(float(x), float(y))
            state.setYaw(float(theta))
            states.append(state)
        return states

    def matrix(self, starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
        distance = self._space.distance
        ends_states = self._states(ends)
        return np.array([[distance(start, end) for end in ends_states]
                         for start in self._states(starts)]) / self._speed


def turn_times(starts: np.ndarray, ends: np.ndarray, config: ControllerConfig) -> np.ndarray:
    """
    Return the times of full-rate turns (either way) that also move the position to the end's.

    Infinite where no turn does: waypoint_controller's TurnPlan decides, so the bench and the
    controller share one criterion.
    """
    limits = plan_limits(config)
    times = np.full((len(starts), len(ends)), np.inf)
    for row, start in enumerate(map(tuple, starts)):
        for column, end in enumerate(map(tuple, ends)):
            offset = (end[0] - start[0], end[1] - start[1])
            turn = wrap_angle(end[2] - start[2])
            for angle in (turn, turn - math.copysign(math.tau, turn)):
                plan = TurnPlan(start, angle, offset, limits)
                if plan.feasible:
                    times[row, column] = min(times[row, column], plan.duration)
    return times


def course_optimum(start, waypoints, config, reeds_shepp):
    """Return (lower bound, chained optimum, the chain's end poses) of one course in seconds."""
    layer = np.array([start], dtype=float)
    cost = np.zeros(1)
    choices, layers, bound = [], [], 0.0
    for waypoint in waypoints:
        samples = goal_set_samples(waypoint, config)
        times = np.minimum(reeds_shepp.matrix(layer, samples), turn_times(layer, samples, config))
        bound += times.min()
        totals = cost[:, None] + times
        choices.append(totals.argmin(axis=0))
        cost = totals.min(axis=0)
        layers.append(samples)
        layer = samples
    index = int(cost.argmin())
    chain = []
    for samples, chosen in zip(reversed(layers), reversed(choices)):
        chain.append(tuple(samples[index]))
        index = int(chosen[index])
    return bound, float(cost.min()), list(reversed(chain))


def inset(pose, waypoint):
    """Move the pose a hair into its goal set."""
    x, y, theta = pose
    dx, dy = waypoint.x - x, waypoint.y - y
    distance = math.hypot(dx, dy)
    step = min(REPLAY_INSET[0], distance)
    if distance > 0.0:
        x, y = x + step * dx / distance, y + step * dy / distance
    turn = wrap_angle(waypoint.theta - theta)
    return x, y, theta + math.copysign(min(REPLAY_INSET[1], abs(turn)), turn)


def replay(start, waypoints, chain, config, dt):
    """Drive the chain in the bench loop: the law aims at the chain's poses."""
    targets = [inset(pose, waypoint) for pose, waypoint in zip(chain, waypoints)]
    return drive(PlannedLaw(waypoints, config, targets=targets), waypoints, start, Loop(dt),
                 config)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--courses', type=int, default=200)
    parser.add_argument('--seed', type=int, default=2026)
    parser.add_argument('--dt', type=float, default=0.05)
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    if args.smoke:
        args.courses = 3
    config = ControllerConfig()
    reeds_shepp = ReedsSheppTimes(config)
    rng = np.random.default_rng(args.seed)
    ratios = {'lower bound (ends free in their goal sets)': [], 'chained optimum': [],
              f'chain replayed at dt {args.dt:g} s': []}
    failures = 0
    for _ in range(args.courses):
        start, waypoints, _ = random_course(rng)
        bound, chained, chain = course_optimum(start, waypoints, config, reeds_shepp)
        run = replay(start, waypoints, chain, config, args.dt)
        failures += not run.success
        base = lower_bound(start, waypoints, config)
        for values, time in zip(ratios.values(), (bound, chained, run.time)):
            values.append(time / base)
    print(f'{args.courses} courses of bench/controller.py (seed {args.seed}): time / LB')
    for label, values in ratios.items():
        print(f'{label:44} median {np.median(values):.3f}  p90 {np.percentile(values, 90):.3f}')
    print(f'replay finished {1 - failures / args.courses:.1%} of the courses')
    return 0


if __name__ == '__main__':
    sys.exit(main())
