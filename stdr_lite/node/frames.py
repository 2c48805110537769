"""
The robots on the TF tree (REP-105, or STDR's), and the markers that show robots and obstacles.

For every robot r (its topic namespace, which is its name unless spawned with another), in
REP-105's tree: map -> r/odom -> r/base_link on /tf with each odometry, and
r/base_link -> r/<sensor> on /tf_static from its description. map -> r/odom is what makes the
chain end at the true pose, as a perfect localiser would publish it: the identity while the
odometry is exact. In STDR's tree (frame_style stdr): map -> map_static, the map's origin, on
/tf_static; map_static -> r, the true pose, on /tf; r -> r_<sensor> on /tf_static; and the
odometry is expressed in map_static. Obstacles have no frames; their markers stand in the map
frame.
"""

from dataclasses import replace

import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from simple_robot_control.pose import compose, invert
from stdr_lite.core.entities import Category
from stdr_lite.core.odometry import OdometryReading
from stdr_lite.core.simulation import Simulation
from stdr_lite.node.messages import obstacle_markers, robot_markers, transform
from stdr_lite.node.parameters import STDR_STATIC_FRAME
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

# tf2_ros's own choices: a deep volatile queue for /tf, the latest message latched for
# /tf_static (so that message holds every static transform of the node).
TF_QOS = QoSProfile(depth=100)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
# The sensor mounts and the markers go out at most this often (wall seconds): each message
# holds every entity, so a burst of 1000 spawns or a crowd of moving obstacles costs one
# message per period, not one per change.
SHOW_PERIOD = 0.05


class FramePublisher:
    """Publishes the TF tree of a simulation's robots, and the markers of every entity."""

    def __init__(self, node, frames, simulation):
        self._frames, self._simulation = frames, simulation
        self._dynamic = node.create_publisher(TFMessage, '/tf', TF_QOS)
        self._static = node.create_publisher(TFMessage, '/tf_static', LATCHED)
        self._markers = node.create_publisher(MarkerArray, '~/robot_markers', LATCHED)
        self._obstacles = node.create_publisher(MarkerArray, '~/obstacle_markers', LATCHED)
        self._entities_changed = self._obstacles_moved = False
        # Each robot's entity, sensor mounts and markers, by name, as last published.
        self._fixed = {}
        self._timer = node.create_timer(SHOW_PERIOD, self._show,
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._timer.cancel()

    def entities_changed(self) -> None:
        """Publish the mounts and every marker anew soon: entities came, went or moved."""
        self._entities_changed = True
        self._show_soon()

    def obstacles_moved(self) -> None:
        """Publish the obstacle markers anew soon."""
        self._obstacles_moved = True
        self._show_soon()

    def _show_soon(self):
        if self._timer.is_canceled():
            self._timer.reset()

    def _show(self):
        self._timer.cancel()
        if self._entities_changed:
            self._publish_fixed(self._simulation)
        if self._entities_changed or self._obstacles_moved:
            self._publish_obstacles(self._simulation)
        self._entities_changed = self._obstacles_moved = False

    def publish_moving(self, simulation: Simulation, time_ns: int) -> None:
        """Publish every robot's moving frames, when anyone listens."""
        if not self._dynamic.get_subscription_count():
            return
        frames = self._frames
        transforms = []
        from_origin = invert(simulation.occupancy_map.origin)
        for name in simulation.robot_names:
            prefix = simulation.entity(name).namespace
            if frames.stdr:
                transforms.append(transform(time_ns, STDR_STATIC_FRAME, frames.base(prefix),
                                            compose(from_origin, simulation.pose(name))))
                continue
            transforms.append(transform(time_ns, frames.map_frame, frames.odom(prefix),
                                        simulation.map_to_odom(name)))
            transforms.append(transform(time_ns, frames.odom(prefix), frames.base(prefix),
                                        simulation.odometry(name).pose))
        self._dynamic.publish(TFMessage(transforms=transforms))

    def odometry_reading(self, simulation: Simulation, name: str) -> OdometryReading:
        """
        Return a robot's odometry as its message gives it.

        That is in its odom frame (REP-105), or in map_static, the map's origin (STDR's), with
        its pose covariance turned alike.
        """
        reading = simulation.odometry(name)
        origin = simulation.occupancy_map.origin
        if not self._frames.stdr or origin == (0.0, 0.0, 0.0):
            return reading
        turn = np.eye(3)
        cos_yaw, sin_yaw = np.cos(-origin[2]), np.sin(-origin[2])
        turn[:2, :2] = ((cos_yaw, -sin_yaw), (sin_yaw, cos_yaw))
        return replace(reading, pose=compose(invert(origin), reading.pose),
                       pose_covariance=turn @ reading.pose_covariance @ turn.T)

    def _publish_fixed(self, simulation):
        """
        Publish the sensor mounts and the markers of the robots there are now.

        Each robot's are made once, when it first shows (a swarm holds thousands), and kept
        while the same robot is there; only the markers' ids follow its place in the list.
        """
        shown = {}
        transforms, markers = [], [Marker(action=Marker.DELETEALL)]
        for index, name in enumerate(simulation.robot_names):
            robot = simulation.robot(name)
            fixed = self._fixed.get(name)
            if fixed is None or fixed[0] is not robot:
                fixed = (robot, *self._fixed_of(robot, simulation.time_ns))
            shown[name] = fixed
            transforms += fixed[1]
            for offset, marker in enumerate(fixed[2]):
                marker.id = 3 * index + offset
            markers += fixed[2]
        self._fixed = shown
        if self._frames.stdr:
            transforms.append(transform(simulation.time_ns, self._frames.map_frame,
                                        STDR_STATIC_FRAME, simulation.occupancy_map.origin))
        self._static.publish(TFMessage(transforms=transforms))
        self._markers.publish(MarkerArray(markers=markers))

    def _fixed_of(self, robot, time_ns):
        """Return a robot's sensor mounts and its markers."""
        frames = self._frames
        mounts = [transform(time_ns, frames.base(robot.namespace),
                            frames.sensor(robot.namespace, sensor.spec), sensor.spec.pose)
                  for sensor in robot.sensors]
        return mounts, robot_markers(robot.name, robot.description.radius,
                                     frames.base(robot.namespace), 0, robot.description.points)

    def _publish_obstacles(self, simulation):
        """Publish every obstacle's markers where it stands now (latched, for late viewers)."""
        markers = [Marker(action=Marker.DELETEALL)]
        for index, name in enumerate(simulation.obstacle_names):
            entity = simulation.entity(name)
            markers += obstacle_markers(name, entity.radius, simulation.pose(name),
                                        entity.category is Category.MOVING_OBSTACLE,
                                        self._frames.map_frame, 2 * index)
        self._obstacles.publish(MarkerArray(markers=markers))
