"""ROS messages of the simulator, filled from the simulation's own state and descriptions."""

import array

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, TransformStamped
from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
from sensor_msgs.msg import LaserScan, Range
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.pose import set_pose, set_yaw
from stdr_lite.core.odometry import OdometryReading
from stdr_lite.core.robot_description import LaserSpec, SonarSpec
from visualization_msgs.msg import Marker

NANOSECONDS = 1_000_000_000
# A variance that claims near certainty without claiming exactness, where drifting odometry
# knows a quantity almost perfectly (a planar robot's height, roll and pitch): consumers that
# invert the covariance get a matrix they can invert.
NEAR_CERTAIN = 1e-9
ROBOT_COLOUR = (0.12, 0.31, 0.86)
OBSTACLE_COLOURS = {False: (0.45, 0.45, 0.45), True: (0.93, 0.55, 0.13)}
OBSTACLE_HEIGHT = 0.5
# The marker namespace of an obstacle's body, by whether it can move.
OBSTACLE_KINDS = {False: 'static_obstacle', True: 'moving_obstacle'}
MARKER_HEIGHT = 0.1
OUTLINE_WIDTH = 0.02
# Places of x, y and yaw in a 6x6 covariance (x, y, z, roll, pitch, yaw).
PLANAR = (0, 1, 5)


def set_stamp(stamp: Time, time_ns: int) -> None:
    """Write a time in nanoseconds into a builtin_interfaces/Time, in place."""
    stamp.sec, stamp.nanosec = divmod(time_ns, NANOSECONDS)


def map_message(occupancy_map: OccupancyMap, frame_id: str) -> OccupancyGrid:
    """Return the map as a nav_msgs/OccupancyGrid in frame_id."""
    message = OccupancyGrid()
    message.header.frame_id = frame_id
    message.info.resolution = occupancy_map.resolution
    message.info.width = occupancy_map.width
    message.info.height = occupancy_map.height
    origin_x, origin_y, yaw = occupancy_map.origin
    message.info.origin.position.x = origin_x
    message.info.origin.position.y = origin_y
    set_yaw(message.info.origin.orientation, yaw)
    # As an array of bytes, the cells pass to the message and on to the middleware as one
    # block: a list of 16 M Python integers would take seconds and a gigabyte.
    message.data = array.array('b', occupancy_map.cells.tobytes())
    return message


def fill_odometry(message: Odometry, time_ns: int, reading: OdometryReading) -> None:
    """
    Write an odometry reading (pose, velocity, their spread) into a nav_msgs/Odometry.

    The planar pose covariance (x, y, yaw) goes into its places of the 6x6 matrix; when the
    reading has any spread, the diagonal gets no zero, so the matrix stays invertible.
    """
    set_stamp(message.header.stamp, time_ns)
    set_pose(message.pose.pose, *reading.pose)
    twist = message.twist.twist
    twist.linear.x, twist.linear.y, twist.angular.z = reading.velocity
    if reading.exact or not (reading.pose_covariance.any() or any(reading.velocity_variance)):
        # Exact odometry: the zeros stay from the last time, unless a spread was written then
        # (its diagonal is never zero).
        if message.pose.covariance[0] != 0.0:
            message.pose.covariance = message.twist.covariance = [0.0] * 36
        return
    pose_covariance = [NEAR_CERTAIN if index % 7 == 0 else 0.0 for index in range(36)]
    twist_covariance = list(pose_covariance)
    for row, row_place in enumerate(PLANAR):
        for column, column_place in enumerate(PLANAR):
            pose_covariance[6 * row_place + column_place] += float(
                reading.pose_covariance[row, column])
    for place, variance in zip((0, 7, 35), reading.velocity_variance):
        twist_covariance[place] += variance
    message.pose.covariance = pose_covariance
    message.twist.covariance = twist_covariance


def transform(time_ns: int, parent: str, child: str, pose: tuple) -> TransformStamped:
    """Return a TransformStamped placing child at the planar pose (x, y, yaw) in parent."""
    message = TransformStamped()
    set_stamp(message.header.stamp, time_ns)
    message.header.frame_id, message.child_frame_id = parent, child
    message.transform.translation.x, message.transform.translation.y = pose[0], pose[1]
    set_yaw(message.transform.rotation, pose[2])
    return message


def sensor_message(frame_id: str, spec: LaserSpec | SonarSpec) -> LaserScan | Range:
    """Return a LaserScan or Range with all but the stamp and the reading filled in."""
    return (_laser_message if isinstance(spec, LaserSpec) else _sonar_message)(frame_id, spec)


def fill_reading(message: LaserScan | Range, reading: np.ndarray | float) -> None:
    """Write a reading (a laser's ranges or a sonar's range) into its message."""
    if isinstance(message, LaserScan):
        message.ranges = reading.astype('float32').tolist()
    else:
        message.range = reading


def robot_markers(name: str, radius: float, base_frame: str, marker_id: int,
                  points: tuple = ()) -> list[Marker]:
    """
    Return the markers RViz shows for a robot: its footprint, its heading and its name.

    The footprint is a disc, or a polygon's outline (a closed line strip through points, its
    corners). They are drawn in the robot's own base frame, so RViz moves them with TF;
    marker_id is the first of the three ids they take.
    """
    if points:
        footprint = _marker(name, 'footprint', marker_id, base_frame, Marker.LINE_STRIP)
        footprint.scale.x = OUTLINE_WIDTH
        footprint.points = [Point(x=float(x), y=float(y), z=0.5 * MARKER_HEIGHT)
                            for x, y in (*points, points[0])]
    else:
        footprint = _marker(name, 'footprint', marker_id, base_frame, Marker.CYLINDER)
        footprint.scale.x = footprint.scale.y = 2.0 * radius
        footprint.scale.z = MARKER_HEIGHT
        footprint.pose.position.z = 0.5 * MARKER_HEIGHT
    heading = _marker(name, 'heading', marker_id + 1, base_frame, Marker.ARROW)
    heading.scale.x, heading.scale.y, heading.scale.z = radius, 0.2 * radius, 0.2 * radius
    heading.pose.position.z = MARKER_HEIGHT
    heading.color.r = heading.color.g = heading.color.b = 1.0
    label = _marker(name, 'name', marker_id + 2, base_frame, Marker.TEXT_VIEW_FACING)
    label.text = name
    label.scale.z = 0.25
    label.pose.position.z = MARKER_HEIGHT + 0.3
    return [footprint, heading, label]


def obstacle_markers(name: str, radius: float, pose: tuple, moving: bool, map_frame: str,
                     marker_id: int) -> list[Marker]:
    """
    Return the markers of an obstacle: a cylinder (grey, or orange if it can move) and its name.

    Obstacles have no frames: the markers stand at the obstacle's pose in the map frame, and
    are published again whenever an obstacle moves. marker_id is the first of the two ids.
    """
    body = _marker(name, OBSTACLE_KINDS[moving], marker_id, map_frame, Marker.CYLINDER,
                   OBSTACLE_COLOURS[moving])
    body.scale.x = body.scale.y = 2.0 * radius
    body.scale.z = OBSTACLE_HEIGHT
    set_pose(body.pose, *pose)
    body.pose.position.z = 0.5 * OBSTACLE_HEIGHT
    label = _marker(name, 'obstacle_name', marker_id + 1, map_frame, Marker.TEXT_VIEW_FACING,
                    OBSTACLE_COLOURS[moving])
    label.text = name
    label.scale.z = 0.25
    set_pose(label.pose, *pose)
    label.pose.position.z = OBSTACLE_HEIGHT + 0.2
    return [body, label]


def _marker(name, namespace, marker_id, frame_id, kind, colour=ROBOT_COLOUR):
    marker = Marker()
    marker.header.frame_id = frame_id
    marker.ns, marker.id, marker.type = namespace, marker_id, kind
    marker.action = Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.color.r, marker.color.g, marker.color.b = colour
    marker.color.a = 1.0
    marker.frame_locked = True
    return marker


def _laser_message(frame_id, spec):
    message = LaserScan()
    message.header.frame_id = frame_id
    message.angle_min, message.angle_max = spec.min_angle, spec.max_angle
    message.angle_increment = ((spec.max_angle - spec.min_angle) / (spec.num_rays - 1)
                               if spec.num_rays > 1 else 0.0)
    message.scan_time = 1.0 / spec.frequency
    message.range_min, message.range_max = spec.min_range, spec.max_range
    return message


def _sonar_message(frame_id, spec):
    message = Range()
    message.header.frame_id = frame_id
    message.radiation_type = Range.ULTRASOUND
    message.field_of_view = spec.cone_angle
    message.min_range, message.max_range = spec.min_range, spec.max_range
    message.variance = spec.noise.std ** 2
    return message
