"""
Planar poses (x, y, theta) to and from ROS messages: the one place each conversion is written.

Duck-typed on the messages' fields, so no ROS import is needed here: a geometry_msgs Pose (or
anything with position and orientation) in, a tuple out, and back. Headings are wrapped by
wrap_angle alone, simulator, controller, lab and grader alike.
"""

import math

import numpy as np
from numpy.typing import ArrayLike


def yaw_from_quaternion(orientation: object) -> float:
    """Heading (rad) of a quaternion with x, y, z, w attributes, about the z axis."""
    return math.atan2(2.0 * (orientation.w * orientation.z + orientation.x * orientation.y),
                      1.0 - 2.0 * (orientation.y ** 2 + orientation.z ** 2))


def set_yaw(orientation: object, yaw: float) -> None:
    """Write a rotation of yaw radians about z into a quaternion message, in place."""
    orientation.x = orientation.y = 0.0
    orientation.z = math.sin(0.5 * yaw)
    orientation.w = math.cos(0.5 * yaw)


def pose_from_message(pose: object) -> tuple:
    """Return (x, y, theta) of a geometry_msgs Pose."""
    return pose.position.x, pose.position.y, yaw_from_quaternion(pose.orientation)


def set_pose(pose: object, x: float, y: float, theta: float) -> None:
    """Write (x, y, theta) into a geometry_msgs Pose, in place (z stays as it is)."""
    pose.position.x, pose.position.y = x, y
    set_yaw(pose.orientation, theta)


def wrap_number(angle: float) -> float:
    """
    Wrap one angle to (-pi, pi]: the rule itself, which the simulator's compiled step uses too.

    Plain Python that numba compiles as it is (stdr_lite/core/kinematics.py): one source.
    """
    wrapped = (angle + math.pi) % math.tau - math.pi
    return math.pi if wrapped == -math.pi else wrapped


def wrap_angle(angle: ArrayLike) -> float | np.ndarray:
    """
    Wrap angles to (-pi, pi]: one value for each heading, the one rule everywhere.

    A number gives a float (wrap_number, a fraction of numpy's per-call cost); an array gives
    an array, to the same bit (numpy's remainder is Python's float modulo).
    """
    if isinstance(angle, (float, int)):
        return wrap_number(angle)
    wrapped = np.remainder(np.asarray(angle, dtype=float) + np.pi, math.tau) - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)[()]


def compose(first: tuple, second: tuple) -> tuple:
    """Return the planar transform first * second: second expressed in first's parent frame."""
    x, y, theta = first
    cos_theta, sin_theta = math.cos(theta), math.sin(theta)
    return (x + cos_theta * second[0] - sin_theta * second[1],
            y + sin_theta * second[0] + cos_theta * second[1],
            wrap_angle(theta + second[2]))


def invert(transform: tuple) -> tuple:
    """Return the inverse of a planar transform (x, y, theta)."""
    x, y, theta = transform
    cos_theta, sin_theta = math.cos(theta), math.sin(theta)
    return (-cos_theta * x - sin_theta * y, sin_theta * x - cos_theta * y, -theta)


def planar_pose(pose: object, tolerance: float = 1e-6) -> tuple:
    """
    Return (x, y, yaw) of a geometry_msgs Pose; ValueError says why it is no planar pose.

    The orientation must be a finite, non-zero quaternion turning about z only (it is
    normalised); z is not used, the world being a plane.
    """
    position, orientation = pose.position, pose.orientation
    values = (position.x, position.y, position.z, orientation.x, orientation.y, orientation.z,
              orientation.w)
    if not all(map(math.isfinite, values)):
        raise ValueError('the pose holds a value that is not finite')
    largest = max(map(abs, values[3:]))
    if largest < tolerance:
        raise ValueError('the orientation is a zero quaternion')
    # Scaled before it is squared, so that no finite quaternion overflows.
    x, y, z, w = (value / largest for value in values[3:])
    norm = math.hypot(x, y, z, w)
    if abs(x) / norm > tolerance or abs(y) / norm > tolerance:
        raise ValueError('the orientation turns about x or y; the world is a plane')
    yaw = wrap_angle(2.0 * math.atan2(z, w))
    return position.x, position.y, yaw
