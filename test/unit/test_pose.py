"""Planar poses from ROS messages, whatever numbers the messages hold."""

import math
from types import SimpleNamespace

import pytest
from simple_robot_control.pose import planar_pose


def pose(x=0.0, y=0.0, qx=0.0, qy=0.0, qz=0.0, qw=1.0):
    return SimpleNamespace(position=SimpleNamespace(x=x, y=y, z=0.0),
                           orientation=SimpleNamespace(x=qx, y=qy, z=qz, w=qw))


@pytest.mark.parametrize('scale', [1e-5, 1.0, 1e200, 1.7e308])
def test_a_quaternion_of_any_size_gives_its_heading(scale):
    assert planar_pose(pose(1.0, 2.0, qz=scale, qw=scale)) == pytest.approx(
        (1.0, 2.0, math.pi / 2))


@pytest.mark.parametrize('message, problem', [
    (pose(qw=0.0), 'zero quaternion'),
    (pose(qx=1e200, qw=1e200), 'turns about x or y'),
    (pose(x=math.inf), 'not finite'),
    (pose(qz=math.nan), 'not finite'),
])
def test_no_planar_pose_is_refused_with_its_reason(message, problem):
    with pytest.raises(ValueError, match=problem):
        planar_pose(message)
