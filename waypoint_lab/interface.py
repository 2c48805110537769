"""
The lab on ROS: the course read, robot_status's QoS, the course as a nav_msgs/Path.

A controller and a monitor of its run (course_monitor, a learned policy's controller) read
the course by the same rules, declare its parameters with the same meaning (parameters.py),
and use the same QoS for robot_status, so any of them can watch or grade any other.
"""

from collections.abc import Sequence

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from simple_robot_control.pose import set_pose
from simple_robot_control.share import shared_file
from simple_robot_control.validation import ConfigError, require
from waypoint_lab.rules import BUNDLED_COURSE
from waypoint_lab.waypoints import load_waypoints, Waypoint, WaypointFileError


def load_course(node: Node, argument: str | None, parameter: str
                ) -> tuple[str, list[Waypoint]]:
    """
    Return (path, waypoints) of the course from the argument, the parameter or the default.

    Giving both is an error, as is a bad file; giving neither picks the bundled course and
    logs that it did.
    """
    require(not (argument and parameter),
            f'waypoint file given twice: argument {argument!r} and parameter '
            f'waypoint_file {parameter!r}; give one')
    path = argument or parameter
    if not path:
        path = shared_file(*BUNDLED_COURSE)
        node.get_logger().info(f'no waypoint file given: using the bundled {BUNDLED_COURSE[-1]}')
    try:
        return path, load_waypoints(path)
    except WaypointFileError as error:
        raise ConfigError(str(error)) from None


def course_message(waypoints: Sequence[Waypoint], frame_id: str) -> Path:
    """Return the course as a nav_msgs/Path in frame_id, a pose per waypoint."""
    path = Path()
    path.header.frame_id = frame_id
    for waypoint in waypoints:
        stamped = PoseStamped()
        stamped.header.frame_id = frame_id
        set_pose(stamped.pose, waypoint.x, waypoint.y, waypoint.theta)
        path.poses.append(stamped)
    return path


def status_qos(waypoint_count: int) -> QoSProfile:
    """Reliable, transient local, and deep enough to replay a whole run to a late subscriber."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=waypoint_count + 2,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
