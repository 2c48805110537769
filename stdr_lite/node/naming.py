"""
What a robot's names become on the ROS graph, checked before the robot exists.

A robot's namespace prefixes its topics (/<namespace>/odom, ...) and its frames
(<namespace>/base_link, ...), and each sensor's frame_id names its topic and frame too. A name
that is fine alone can still make a topic longer than ROS allows, or a sensor frame that is
the robot's own odometry or body frame; creating such a topic would kill the node, so every
robot is checked first, at start and at every spawn.
"""

from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.node import Node
from simple_robot_control.node_runtime import rcl_problem
from simple_robot_control.validation import shorten
from stdr_lite.core.robot_description import ROBOT_TOPICS, RobotDescription
from stdr_lite.node.parameters import Frames

# rmw's limit: 255 characters less 8 for the middleware's own prefixes and suffixes.
MAX_TOPIC_LENGTH = 247


class NamingProblem(ValueError):
    """A robot whose names cannot all exist; part says whether its name or a sensor is to blame."""

    def __init__(self, part, message):
        super().__init__(message)
        self.part = part


def check_robot_names(node: Node, frames: Frames, namespace: str,
                      description: RobotDescription) -> None:
    """
    Raise NamingProblem unless every topic and frame of the robot can exist.

    part is 'name' when the robot's own topics cannot (its namespace is too long), 'sensor'
    when a sensor's frame_id is at fault.
    """
    for spec in description.lasers + description.sonars:
        for role, frame in (('odometry', frames.odom_frame), ('body', frames.base_frame)):
            if spec.frame_id == frame:
                raise NamingProblem('sensor', f'sensor frame_id {spec.frame_id!r} is the '
                                    f"robot's own {role} frame ({namespace}/{frame}); name "
                                    'the sensor otherwise')
    leaves = [(leaf, 'name') for leaf in ROBOT_TOPICS] + [
        (spec.frame_id, 'sensor') for spec in description.lasers + description.sonars]
    for leaf, part in leaves:
        relative = f'{namespace}/{leaf}'
        try:
            node.resolve_topic_name(relative)
        except rclpy_implementation.RCLError as error:
            expanded = f'{node.get_namespace().rstrip("/")}/{relative}'
            if len(expanded) > MAX_TOPIC_LENGTH:
                problem = (f'its topic {shorten(expanded)} would be {len(expanded)} '
                           f'characters long; ROS allows at most {MAX_TOPIC_LENGTH}')
            else:
                problem = f'its topic {shorten(expanded)} is no ROS topic: {rcl_problem(error)}'
            raise NamingProblem(part, problem + (
                ': shorten its name or namespace' if part == 'name'
                else f': shorten the sensor frame_id {shorten(leaf)}')) from None
