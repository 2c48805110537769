"""foxglove_live's parameter table: plain data, light to load (see early_parameters.py)."""

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds

PARAMETERS = (
    ParameterSpec('host', '127.0.0.1', 'the address to serve on: 127.0.0.1 is this machine only '
                  '(reach it from another through ssh -L 8765:localhost:8765); 0.0.0.0 opens it '
                  'to the network, with no authentication'),
    ParameterSpec('port', 8765, 'the TCP port to serve on (0: a free one, printed)',
                  bounds=Bounds(0, 65535)),
    ParameterSpec('topics', ('*',), 'the topics to offer: full names or patterns (* and ?, as '
                  'in shell globs); each is subscribed only while a client shows it'),
    ParameterSpec('command_topics', ('*/cmd_vel',), 'the topics clients may publish on '
                  '(geometry_msgs Twist or TwistStamped, as the Teleop panel sends): names or '
                  'patterns; nothing else can be published through Foxglove'),
    ParameterSpec('bag', '', 'also record the offered topics into this bag, an .mcap file '
                  "(replaced if it exists); '' records nothing"),
)
