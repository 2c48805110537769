"""robot_status texts as the lab specifies them."""

import math

from waypoint_controller.status import aborted, finished, started, waypoint_reached


def test_messages_carry_poses_with_theta_in_degrees():
    assert started((1.0, 2.0, 0.0)) == 'STARTED 1.000 2.000 0.00'
    assert waypoint_reached(3, (4.5, -1.25, math.pi / 2)) == 'WAYPOINT 3 4.500 -1.250 90.00'
    assert aborted(2, (0.0, 0.0, -math.pi)) == 'ABORTED 2 0.000 0.000 -180.00'
    assert finished() == 'FINISHED'
