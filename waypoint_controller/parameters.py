"""waypoint_controller's parameter table: plain data, light to load (see early_parameters.py)."""

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds
from waypoint_controller.config import ControllerConfig
from waypoint_lab.parameters import RUNNER_PARAMETERS

GAIN = Bounds(0.0, 1000.0)
PROPORTIONAL_GAIN = Bounds(0.0, 1000.0, low_open=True)

DEFAULTS = ControllerConfig()
PARAMETERS = RUNNER_PARAMETERS + (
    ParameterSpec('heading_kp', DEFAULTS.heading_kp, 'heading PID proportional gain [1/s]',
                  PROPORTIONAL_GAIN, tunable=True),
    ParameterSpec('heading_ki', DEFAULTS.heading_ki, 'heading PID integral gain [1/s^2]', GAIN,
                  tunable=True),
    ParameterSpec('heading_kd', DEFAULTS.heading_kd, 'heading PID derivative gain [-]', GAIN,
                  tunable=True),
    ParameterSpec('distance_kp', DEFAULTS.distance_kp, 'distance PID proportional gain [1/s]',
                  PROPORTIONAL_GAIN, tunable=True),
    ParameterSpec('distance_ki', DEFAULTS.distance_ki, 'distance PID integral gain [1/s^2]',
                  GAIN, tunable=True),
    ParameterSpec('distance_kd', DEFAULTS.distance_kd, 'distance PID derivative gain [-]', GAIN,
                  tunable=True),
    ParameterSpec('robot_radius', 0.2, 'footprint radius kept off the walls of /map, when '
                  'a map is published [m]', Bounds(0.0, 10.0)),
)
