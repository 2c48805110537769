"""The parameter tables of stdr_lite's tools: plain data, light to load (early_parameters.py)."""

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds

MOVE_ROBOT_PARAMETERS = (
    ParameterSpec('robot_name', 'robot0', 'robot to drive: topics <name>/cmd_vel and '
                  '<name>/odom', ros_name=True),
    ParameterSpec('odom_timeout', 10.0, 'give up when no odometry arrives for this long '
                  '[s of wall time]', Bounds(0.0, 3600.0, low_open=True)),
    ParameterSpec('cmd_vel_stamped', False, 'send commands as geometry_msgs/TwistStamped, for a '
                  'simulator that takes them so'),
    ParameterSpec('simulator', 'stdr_lite', "the simulator's node, whose simulation_interfaces "
                  'API (pause, simulate_steps) holds each command for exactly its duration; '
                  'without it, moves are timed by the odometry and may end a step late',
                  ros_name=True),
)
