"""
The controller benchmark's courses and its loop, for bench/controller.py and bench/optimum.py.

Courses are seeded and mix open legs with the hard kinds (a goal behind, a sidestep, a turn on
the spot). The loop integrates exact arcs and judges each goal set after every step on the pose
the controller sees (the odometry, which may drift).
"""

from collections import deque
from dataclasses import dataclass, field
import math

from simple_robot_control.pose import wrap_angle as wrap
from stdr_lite.core.kinematics import arc_step
from stdr_lite.core.odometry import Odometry
from stdr_lite.core.setting_values import OdometryNoise
from stdr_lite.core.state import StateTable
from waypoint_lab.lifecycle import RunLifecycle, RunRules
from waypoint_lab.waypoints import Waypoint

LEG_KINDS = ('open', 'behind', 'lateral', 'rotation')
LEG_WEIGHTS = (0.55, 0.15, 0.15, 0.15)


def random_course(rng, waypoint_count=5):
    """Return a start pose, waypoints mixing open legs with the hard kinds, and the kinds."""
    x, y, theta = 0.0, 0.0, rng.uniform(-math.pi, math.pi)
    start = (x, y, theta)
    waypoints = []
    kinds = [str(kind) for kind in rng.choice(LEG_KINDS, size=waypoint_count, p=LEG_WEIGHTS)]
    for kind in kinds:
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
    return start, waypoints, kinds


def lower_bound(start, waypoints, config):
    """LB: each leg's distance and turn less the tolerances, at full speed or full rate."""
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


# Drift of a typical wheeled robot, as the README suggests for stdr_lite's odom_noise_*.
TYPICAL_DRIFT = OdometryNoise(distance=0.02, turn=0.05, heading_per_distance=0.02)


@dataclass
class Run:
    success: bool
    time: float
    path_length: float
    reversals: int
    leg_times: list = field(default_factory=list)


@dataclass(frozen=True)
class Loop:
    """How the bench loop runs: step, control period, command latency and odometry drift."""

    dt: float
    control_every: int = 1
    late_by: int = 0
    drift: OdometryNoise = OdometryNoise()


def drive(law, waypoints, start, loop: Loop, config):
    """
    Run one course through the lab's run lifecycle and time each of its legs.

    Every step the goal is checked on the odometry pose; every control period the law's
    command is taken, to be applied late_by control periods later; then one exact-arc step is
    taken. The run has the course's time limit (time_limit) and no stall abort before it.
    """
    limit = time_limit(start, waypoints, config)
    run = RunLifecycle(waypoints, law, RunRules(
        config.distance_tolerance, config.angle_tolerance, config.max_linear_speed,
        config.max_angular_speed, stall_timeout=limit,
        control_period_ns=round(loop.dt * loop.control_every * 1e9)))
    pose, seen = start, start
    odometry = (Odometry(StateTable.of_bodies([start]), loop.drift, seed=0)
                if loop.drift.enabled else None)
    queue = deque([(0.0, 0.0)] * loop.late_by)
    command = (0.0, 0.0)
    path_length, reversals, last_sign, elapsed, step_index = 0.0, 0, 0.0, 0.0, 0
    leg_started, leg_times = 0.0, []
    while elapsed <= limit:
        outcome = run.observe(round(step_index * loop.dt * 1e9), seen)
        if outcome.exit_code is None and outcome.command is not None:
            queue.append(outcome.command)
            command = queue.popleft()
        for _ in outcome.reached:
            leg_times.append(elapsed - leg_started)
            leg_started = elapsed
        if outcome.exit_code is not None:
            return Run(outcome.exit_code == 0, elapsed, path_length, reversals, leg_times)
        linear, angular = command
        sign = math.copysign(1.0, angular) if abs(angular) > 1e-3 else 0.0
        if sign and last_sign and sign != last_sign:
            reversals += 1
        last_sign = sign or last_sign
        x, y, theta = (float(value) for value in arc_step(*pose, linear, angular, loop.dt))
        path_length += math.hypot(x - pose[0], y - pose[1])
        pose = (x, y, theta)
        if odometry is None:
            seen = pose
        else:
            odometry.state.pose[0] = pose
            odometry.state.applied[0] = (linear, 0.0, angular)
            odometry.advance(loop.dt)
            seen = odometry.reading(0).pose
        elapsed += loop.dt
        step_index += 1
    return Run(False, elapsed, path_length, reversals, leg_times)


def time_limit(start, waypoints, config):
    """Seconds after which a run counts as failed."""
    return 10.0 * lower_bound(start, waypoints, config) + 30.0
