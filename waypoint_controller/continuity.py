"""
Whether two odometry poses in a row can be the robot's own motion. Pure Python, no ROS.

A robot under a controller moves no faster than the controller commands it; a pose that jumps
further than that between two stamps was put there by someone else (a teleport, RViz's "2D
Pose Estimate", a reset of the simulation), and the run it belonged to is over.
"""

import math

from simple_robot_control.pose import wrap_angle

# Slack on top of twice the commanded limits: drift, rounding, a simulator's own clamping.
JUMP_DISTANCE = 0.1
JUMP_ANGLE = 0.2


def jump_problem(previous: tuple, pose: tuple, seconds: float, max_linear: float,
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
    return (f'moved from ({before}) to ({after}) in {seconds:.3f} s, {distance:.3g} m and '
            f'{math.degrees(turn):.3g} deg: faster than it is driven')
