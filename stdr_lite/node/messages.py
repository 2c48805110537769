"""ROS messages of the simulator, filled from the simulation's own descriptions."""

from nav_msgs.msg import OccupancyGrid
from sensor_msgs.msg import LaserScan, Range
from simple_robot_control.pose import set_yaw
from stdr_lite.core.robot_description import LaserSpec

NANOSECONDS = 1_000_000_000


def set_stamp(stamp, time_ns):
    """Write a time in nanoseconds into a builtin_interfaces/Time, in place."""
    stamp.sec, stamp.nanosec = divmod(time_ns, NANOSECONDS)


def map_message(occupancy_map, frame_id):
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
    message.data = occupancy_map.cells.ravel().tolist()
    return message


def sensor_message(robot_name, spec):
    """Return a LaserScan or Range with all but the stamp and the reading filled in."""
    return (_laser_message if isinstance(spec, LaserSpec) else _sonar_message)(robot_name, spec)


def fill_reading(message, reading):
    """Write a reading (a laser's ranges or a sonar's range) into its message."""
    if isinstance(message, LaserScan):
        message.ranges = reading.astype('float32').tolist()
    else:
        message.range = reading


def _laser_message(robot_name, spec):
    message = LaserScan()
    message.header.frame_id = f'{robot_name}/{spec.frame_id}'
    message.angle_min, message.angle_max = spec.min_angle, spec.max_angle
    message.angle_increment = ((spec.max_angle - spec.min_angle) / (spec.num_rays - 1)
                               if spec.num_rays > 1 else 0.0)
    message.scan_time = 1.0 / spec.frequency
    message.range_min, message.range_max = spec.min_range, spec.max_range
    return message


def _sonar_message(robot_name, spec):
    message = Range()
    message.header.frame_id = f'{robot_name}/{spec.frame_id}'
    message.radiation_type = Range.ULTRASOUND
    message.field_of_view = spec.cone_angle
    message.min_range, message.max_range = spec.min_range, spec.max_range
    message.variance = spec.noise.std ** 2
    return message
