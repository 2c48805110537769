"""stdr_viewer's parameter table: plain data, light to load (see early_parameters.py)."""

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds
from stdr_lite.node.parameters import RESOURCE_PATHS

PARAMETERS = (
    ParameterSpec('robot_description', '', "robot file giving the robots' footprint and "
                  'sensor mounts where the simulator publishes no markers and /tf_static (as '
                  'stdr_lite does); empty for the bundled lab robot'),
    RESOURCE_PATHS,
    ParameterSpec('width', 1000, 'window width [pixels]', Bounds(200, 10000)),
    ParameterSpec('height', 750, 'window height [pixels]', Bounds(150, 10000)),
    ParameterSpec('fps', 30.0, 'frames drawn per second of wall time', Bounds(1.0, 120.0)),
    ParameterSpec('screenshot', '', 'write the last frame to this PNG file on exit; empty: '
                  'none'),
)
