"""The text of robot_status messages, as the lab specifies them (theta in degrees)."""

import math


def _pose_text(pose):
    x, y, theta = pose
    return f'{x:.3f} {y:.3f} {math.degrees(theta):.2f}'


def started(pose):
    return f'STARTED {_pose_text(pose)}'


def waypoint_reached(number, pose):
    return f'WAYPOINT {number} {_pose_text(pose)}'


def finished():
    return 'FINISHED'


def aborted(number, pose):
    return f'ABORTED {number} {_pose_text(pose)}'
