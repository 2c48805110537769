"""
Estimate how fast the controller benchmark's courses can be driven (a benchmark, not a test).

For each course of bench/controller.py, every leg is given the fastest path of one family:
pivot, then a Dubins word at the turning radius v_max/omega_max or rotate-straight-rotate
(forward or backward), then pivot, the pivots searched on a grid. Legs run from the exact
waypoint to the exact next one, so the goal-set tolerance is not used; the second figure
credits every leg a fixed allowance for it. Neither is a proof of optimality: the family has
no cusps inside a leg and no tighter arcs. It shows what the controller's T/LB could be.
"""

import argparse
import math
import sys

from bench.controller import lower_bound, random_course
from bench.reference_paths import candidate_paths
import numpy as np
from waypoint_controller.control_law import ControllerConfig


def fastest_leg(start, goal, config, pivot_grid):
    """Seconds of the fastest pivot + path + pivot from start to goal (poses x, y, theta)."""
    speed, rate = config.max_linear_speed, config.max_angular_speed
    best = math.inf
    for first in pivot_grid:
        turned = (start[0], start[1], start[2] + first)
        for last in pivot_grid:
            pivots = (abs(first) + abs(last)) / rate
            if pivots >= best:
                continue
            before_last = (goal[0], goal[1], goal[2] - last)
            for path in candidate_paths(turned, before_last, (speed / rate,)):
                best = min(best, pivots + path.duration(speed, rate))
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--courses', type=int, default=200)
    parser.add_argument('--seed', type=int, default=2026)
    parser.add_argument('--pivot-step', type=float, default=10.0, help='pivot grid [degrees]')
    parser.add_argument('--allowance', type=float, default=0.2,
                        help='seconds credited per leg for the goal-set tolerance')
    args = parser.parse_args(argv)
    config = ControllerConfig()
    pivot_grid = np.radians(np.arange(-180.0, 180.0, args.pivot_step))
    rng = np.random.default_rng(args.seed)
    exact, credited = [], []
    for _ in range(args.courses):
        start, waypoints = random_course(rng)
        total, previous = 0.0, start
        for waypoint in waypoints:
            goal = (waypoint.x, waypoint.y, waypoint.theta)
            total += fastest_leg(previous, goal, config, pivot_grid)
            previous = goal
        bound = lower_bound(start, waypoints, config)
        exact.append(total / bound)
        credited.append((total - args.allowance * len(waypoints)) / bound)
    print(f'{args.courses} courses of bench/controller.py (seed {args.seed}), pivot + Dubins or '
          f'rotate-straight-rotate + pivot per leg, pivots every {args.pivot_step:g} deg')
    for label, ratios in (('exact waypoints', exact),
                          (f'less {args.allowance:g} s per leg', credited)):
        print(f'{label:24} T/LB median {np.median(ratios):.3f}  '
              f'p90 {np.percentile(ratios, 90):.3f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
