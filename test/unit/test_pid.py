"""The PID: proportional, integral and derivative terms, saturation and anti-windup."""

import pytest
from waypoint_controller.pid import PID


def test_terms_add_up():
    pid = PID(kp=2.0, ki=0.5, kd=0.1)
    assert pid.update(1.0, 0.1) == pytest.approx(2.0 + 0.05)
    assert pid.update(3.0, 0.1) == pytest.approx(6.0 + 0.5 * 0.4 + 0.1 * 20.0)


def test_output_is_saturated():
    pid = PID(kp=10.0, output_limit=1.5)
    assert pid.update(4.0, 0.1) == 1.5
    assert pid.update(-4.0, 0.1) == -1.5


def test_integral_does_not_wind_up_while_saturated():
    pid = PID(kp=1.0, ki=1.0, output_limit=1.0)
    for _ in range(1000):
        pid.update(5.0, 0.1)
    assert pid.update(-0.5, 0.1) < 0.0


def test_proportional_gain_can_be_overridden_per_step():
    pid = PID(kp=10.0)
    assert pid.update(0.5, 0.1, kp=1.0) == pytest.approx(0.5)


def test_reset_forgets_history():
    pid = PID(kp=0.0, ki=1.0, kd=1.0)
    pid.update(1.0, 1.0)
    pid.reset()
    assert pid.update(1.0, 1.0) == pytest.approx(1.0)


def test_negative_gains_are_refused():
    with pytest.raises(ValueError):
        PID(kp=-1.0)
