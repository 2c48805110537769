"""Conversions between planar headings and quaternions."""

import math


def yaw_from_quaternion(orientation):
    """Heading (rad) of a quaternion with x, y, z, w attributes, about the z axis."""
    return math.atan2(2.0 * (orientation.w * orientation.z + orientation.x * orientation.y),
                      1.0 - 2.0 * (orientation.y ** 2 + orientation.z ** 2))
