"""Both integrators against closed-form unicycle motion."""

import math

import numpy as np
import pytest
from simple_robot_control.pose import wrap_angle
from stdr_lite.core.kinematics import arc_step, euler_step


def closed_form_arc(x, y, theta, v, omega, t):
    """Exact pose after t seconds at constant (v, omega), written as a circle about its centre."""
    radius = v / omega
    centre_x, centre_y = x - radius * math.sin(theta), y + radius * math.cos(theta)
    heading = theta + omega * t
    return centre_x + radius * math.sin(heading), centre_y - radius * math.cos(heading), heading


def test_euler_step_is_the_labs_equation_2():
    x, y, theta = euler_step(1.0, 2.0, 0.3, 0.7, 0.5, 0.1)
    assert x == pytest.approx(1.0 + 0.07 * math.cos(0.3))
    assert y == pytest.approx(2.0 + 0.07 * math.sin(0.3))
    assert theta == pytest.approx(0.35)


@pytest.mark.parametrize('v, omega, t', [(1.0, 0.5, 2.0), (-0.4, 1.3, 0.7), (2.0, -3.0, 1.9)])
def test_arc_step_matches_the_closed_form_circle(v, omega, t):
    expected_x, expected_y, expected_theta = closed_form_arc(0.5, -1.0, 0.9, v, omega, t)
    x, y, theta = arc_step(0.5, -1.0, 0.9, v, omega, t)
    assert (x, y) == pytest.approx((expected_x, expected_y), abs=1e-12)
    assert theta == pytest.approx(wrap_angle(expected_theta), abs=1e-12)


def test_arc_step_without_rotation_is_a_straight_line():
    x, y, theta = arc_step(1.0, 1.0, math.pi / 6, 2.0, 0.0, 1.5)
    assert (x, y) == pytest.approx((1.0 + 3.0 * math.cos(math.pi / 6),
                                    1.0 + 3.0 * math.sin(math.pi / 6)))
    assert theta == pytest.approx(math.pi / 6)


def test_many_small_arc_steps_equal_one_large_step():
    pose = (0.0, 0.0, 0.2)
    for _ in range(100):
        pose = arc_step(*pose, 0.8, 0.6, 0.05)
    assert pose == pytest.approx(arc_step(0.0, 0.0, 0.2, 0.8, 0.6, 5.0), abs=1e-9)


def test_euler_converges_to_the_arc_at_first_order():
    exact = np.array(closed_form_arc(0.0, 0.0, 0.0, 1.0, 1.0, 1.0)[:2])
    errors = []
    for steps in (10, 100, 1000):
        pose = (0.0, 0.0, 0.0)
        for _ in range(steps):
            pose = euler_step(*pose, 1.0, 1.0, 1.0 / steps)
        errors.append(np.linalg.norm(np.array(pose[:2]) - exact))
    assert errors[1] == pytest.approx(errors[0] / 10, rel=0.1)
    assert errors[2] == pytest.approx(errors[1] / 10, rel=0.1)


def test_vectorized_steps_equal_one_robot_at_a_time():
    rng = np.random.default_rng(3)
    x, y, theta, v, omega = rng.uniform(-2, 2, size=(5, 8))
    for step in (euler_step, arc_step):
        together = step(x, y, theta, v, omega, 0.1)
        for i in range(8):
            alone = step(x[i], y[i], theta[i], v[i], omega[i], 0.1)
            assert [part[i] for part in together] == pytest.approx(list(alone))


@pytest.mark.parametrize('angle, wrapped', [(math.pi, math.pi), (-math.pi, math.pi),
                                            (3 * math.pi, math.pi), (2 * math.pi, 0.0),
                                            (-0.5, -0.5), (7.0, 7.0 - 2 * math.pi)])
def test_wrap_angle_lands_in_half_open_interval(angle, wrapped):
    assert wrap_angle(angle) == pytest.approx(wrapped)
