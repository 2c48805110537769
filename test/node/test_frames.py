"""stdr_lite on the TF tree: REP-105 frames, drifting odometry, ground truth, RViz markers."""

import math

from geometry_msgs.msg import Twist, TwistStamped
from map_fixtures import walled_room, write_map
from nav_msgs.msg import Odometry
import pytest
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.time import Time
from ros_helpers import overrides, pose_stamped, ServiceCaller, spin_until
from sensor_msgs.msg import LaserScan, Range
from simple_robot_control.pose import compose, pose_from_message, yaw_from_quaternion
from simple_robot_control.share import BUNDLED_ROBOT, shared_file
from simple_robot_control.validation import ConfigError
from simulation_interfaces.srv import SpawnEntity
from stdr_lite.core.robot_description import load_robot
from stdr_lite.node.stdr_lite import StdrLite
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
DRIFT = {'odom_noise_distance': 0.05, 'odom_noise_turn': 0.05,
         'odom_noise_heading_per_distance': 0.02}


def stamp_of(message):
    return Time.from_msg(message.header.stamp).nanoseconds


class Listener(Node):
    """
    Answers robot0's odometry with a curve in lockstep, and keeps what it hears by stamp.

    A stamp is answered once its ground truth and its /tf are in too, so every step's are
    heard (the simulator sends them again, with the same stamp, to an unanswered step).
    """

    def __init__(self, context, stamped=False, steps=60):
        super().__init__('listener', context=context)
        self.odometry, self.truth, self.tf, self.static = {}, {}, [], []
        self.scans, self.ranges = [], []
        self.answered = 0
        self._answered, self._tf_stamps = set(), set()
        self._steps = steps
        self._command = self.create_publisher(TwistStamped if stamped else Twist,
                                              '/robot0/cmd_vel', 10)
        self.create_subscription(Odometry, '/robot0/odom', self._on_odometry, 100)
        self.create_subscription(Odometry, '/robot0/ground_truth', self._on_truth, 100)
        self.create_subscription(TFMessage, '/tf', self._on_tf, 100)
        self.create_subscription(TFMessage, '/tf_static', self.static.append, LATCHED)
        self.create_subscription(LaserScan, '/robot0/laser_0', self.scans.append, 10)
        self.create_subscription(Range, '/robot0/sonar_3', self.ranges.append, 10)

    def _on_tf(self, message):
        self.tf.append(message)
        for stamp in {stamp_of(transform) for transform in message.transforms}:
            self._tf_stamps.add(stamp)
            self._answer(stamp)

    def _on_truth(self, message):
        self.truth.setdefault(stamp_of(message), message)
        self._answer(stamp_of(message))

    def _on_odometry(self, message):
        self.odometry.setdefault(stamp_of(message), message)
        self._answer(stamp_of(message))

    def _answer(self, stamp):
        if (stamp in self._answered or stamp not in self.odometry or stamp not in self.truth
                or stamp not in self._tf_stamps or self.answered >= self._steps):
            return
        self._answered.add(stamp)
        twist = Twist()
        twist.linear.x, twist.angular.z = 0.4, 0.6 * math.sin(stamp * 1e-9)
        if isinstance(self._command.msg_type(), TwistStamped):
            command = TwistStamped()
            command.twist = twist
            twist = command
        self._command.publish(twist)
        self.answered += 1


def run_lockstep(ros_context, executor, stamped=False, steps=60, **params):
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        lockstep=True, real_time_factor=0.0, cmd_vel_stamped=stamped, **params))
    listener = Listener(ros_context, stamped, steps)
    executor.add_node(simulator)
    executor.add_node(listener)
    spin_until(executor, lambda: listener.answered >= steps, what='the answered steps')
    spin_until(executor, lambda: len(listener.truth) >= steps and len(listener.tf) >= steps,
               what='ground truth and TF of every step')
    return simulator, listener


def planar(transform):
    """Return {(parent, child): (x, y, yaw)} of a TransformStamped."""
    pose = (transform.transform.translation.x, transform.transform.translation.y,
            yaw_from_quaternion(transform.transform.rotation))
    return {(transform.header.frame_id, transform.child_frame_id): pose}


def tree_of(tf_messages, stamp):
    """Return {(parent, child): (x, y, yaw)} of the /tf messages with this stamp."""
    tree = {}
    for message in tf_messages:
        for transform in message.transforms:
            if Time.from_msg(transform.header.stamp).nanoseconds == stamp:
                tree.update(planar(transform))
    return tree


@pytest.mark.parametrize('drift', [{}, DRIFT], ids=['exact', 'drifting'])
def test_map_odom_base_link_is_the_ground_truth_at_every_step(ros_context, executor, drift):
    _, listener = run_lockstep(ros_context, executor, **drift)
    for stamp, odometry in listener.odometry.items():
        tree = tree_of(listener.tf, stamp)
        assert tree[('robot0/odom', 'robot0/base_link')] == pytest.approx(
            pose_from_message(odometry.pose.pose), abs=1e-9)
        chained = compose(tree[('map', 'robot0/odom')], tree[('robot0/odom', 'robot0/base_link')])
        truth = pose_from_message(listener.truth[stamp].pose.pose)
        assert chained[:2] == pytest.approx(truth[:2], abs=1e-6)
        assert math.remainder(chained[2] - truth[2], math.tau) == pytest.approx(0.0, abs=1e-6)
        if not drift:
            assert tree[('map', 'robot0/odom')] == (0.0, 0.0, 0.0)
    last = max(listener.odometry)
    drifted = math.dist(pose_from_message(listener.odometry[last].pose.pose)[:2],
                        pose_from_message(listener.truth[last].pose.pose)[:2])
    assert (drifted > 1e-4) == bool(drift)


def test_every_message_is_in_its_frame(ros_context, executor):
    _, listener = run_lockstep(ros_context, executor, steps=15)
    spin_until(executor, lambda: listener.scans and listener.ranges, what='sensor readings')
    assert listener.scans[0].header.frame_id == 'robot0/laser_0'
    assert listener.ranges[0].header.frame_id == 'robot0/sonar_3'
    odometry = next(iter(listener.odometry.values()))
    truth = next(iter(listener.truth.values()))
    assert (odometry.header.frame_id, odometry.child_frame_id) == ('robot0/odom',
                                                                   'robot0/base_link')
    assert (truth.header.frame_id, truth.child_frame_id) == ('map', 'robot0/base_link')
    assert set(tree_of(listener.tf, stamp_of(odometry))) == {
        ('map', 'robot0/odom'), ('robot0/odom', 'robot0/base_link')}


def test_sensor_mounts_are_static_transforms_from_the_description(ros_context, executor):
    _, listener = run_lockstep(ros_context, executor, steps=5)
    spin_until(executor, lambda: listener.static, what='/tf_static')
    mounts = {}
    for transform in listener.static[-1].transforms:
        mounts.update(planar(transform))
    description = load_robot(shared_file(*BUNDLED_ROBOT))
    expected = {('robot0/base_link', f'robot0/{spec.frame_id}'): spec.pose
                for spec in description.lasers + description.sonars}
    assert set(mounts) == set(expected)
    for frames, pose in expected.items():
        assert mounts[frames] == pytest.approx(pose)


def test_stdr_frames_compose_to_the_ground_truth(ros_context, executor, tmp_path):
    """The tree is STDR's: map -> map_static (the map's origin) -> robot0 -> robot0_<sensor>."""
    origin = (-1.0, 0.5, 0.3)
    world = write_map(tmp_path, walled_room(400, 300), origin=list(origin))
    _, listener = run_lockstep(ros_context, executor, steps=20, frame_style='stdr',
                               map_yaml=str(world), initial_pose=[3.0, 3.0, 0.5])
    spin_until(executor, lambda: listener.static and listener.scans, what='/tf_static, a scan')
    fixed = {}
    for transform in listener.static[-1].transforms:
        fixed.update(planar(transform))
    assert fixed[('map', 'map_static')] == pytest.approx(origin)
    assert fixed[('robot0', 'robot0_laser_0')] == pytest.approx((0.1, 0.0, 0.0))
    assert listener.scans[-1].header.frame_id == 'robot0_laser_0'
    for stamp, odometry in listener.odometry.items():
        assert (odometry.header.frame_id, odometry.child_frame_id) == ('map_static', 'robot0')
        tree = tree_of(listener.tf, stamp)
        assert set(tree) == {('map_static', 'robot0')}
        assert pose_from_message(odometry.pose.pose) == pytest.approx(
            tree[('map_static', 'robot0')], abs=1e-9)
        truth = listener.truth[stamp]
        assert (truth.header.frame_id, truth.child_frame_id) == ('map', 'robot0')
        chained = compose(fixed[('map', 'map_static')], tree[('map_static', 'robot0')])
        assert chained == pytest.approx(pose_from_message(truth.pose.pose), abs=1e-6)


def test_stdr_frames_leave_no_rep105_frame_name_unused(ros_context):
    with pytest.raises(ConfigError, match='base_frame_id: REP-105 frames; with frame_style '
                       "stdr a robot's body frame is its name"):
        StdrLite(context=ros_context, parameter_overrides=overrides(
            frame_style='stdr', base_frame_id='body'))


def test_drifting_odometry_reports_a_covariance_that_grows(ros_context, executor):
    _, listener = run_lockstep(ros_context, executor, **DRIFT)
    covariances = [listener.odometry[stamp].pose.covariance for stamp in sorted(listener.odometry)]
    traces = [covariance[0] + covariance[7] + covariance[35] for covariance in covariances]
    assert traces[-1] > traces[len(traces) // 2] > traces[1] > 0.0
    last = covariances[-1]
    assert all(last[7 * index] > 0.0 for index in range(6))
    assert listener.odometry[max(listener.odometry)].twist.covariance[0] > 0.0


def test_exact_odometry_has_no_spread(ros_context, executor):
    _, listener = run_lockstep(ros_context, executor, steps=10)
    assert not any(any(message.pose.covariance) for message in listener.odometry.values())


def test_stamped_commands_drive_the_robot(ros_context, executor):
    _, listener = run_lockstep(ros_context, executor, stamped=True, steps=30)
    last = listener.odometry[max(listener.odometry)]
    assert last.twist.twist.linear.x == pytest.approx(0.4)
    assert pose_from_message(last.pose.pose)[0] > 1.2


def test_odometry_goes_out_at_its_own_rate_and_lockstep_follows_it(ros_context, executor):
    _, listener = run_lockstep(ros_context, executor, steps=10, odom_rate_hz=10.0)
    stamps = sorted(listener.odometry)
    assert {b - a for a, b in zip(stamps, stamps[1:])} == {100_000_000}


def test_every_robot_has_markers_and_the_set_follows_the_robots(ros_context, executor, tmp_path):
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots:\n  - {pose: [2.0, 2.0, 0.0]}\n  - {name: scout, pose: [5.0, 5.0, '
                      '0.0]}\n')
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        robots_file=str(robots), real_time_factor=0.0))
    watcher = Node('watcher', context=ros_context)
    markers = []
    watcher.create_subscription(MarkerArray, '/stdr_lite/robot_markers', markers.append, LATCHED)
    obstacles = []
    watcher.create_subscription(MarkerArray, '/stdr_lite/obstacle_markers', obstacles.append,
                                LATCHED)
    for node in (simulator, watcher):
        executor.add_node(node)

    def footprints():
        return {(marker.header.frame_id, marker.scale.x) for marker in markers[-1].markers
                if marker.ns == 'footprint'} if markers else set()

    spin_until(executor, lambda: footprints() == {('robot0/base_link', 0.4),
                                                  ('scout/base_link', 0.4)}, what='markers')
    assert markers[-1].markers[0].action == Marker.DELETEALL
    assert {marker.text for marker in markers[-1].markers if marker.ns == 'name'} == {
        'robot0', 'scout'}
    call = ServiceCaller(executor, watcher)
    call(SpawnEntity, 'spawn_entity', name='third', uri='lab_robot',
         initial_pose=pose_stamped(8.0, 8.0))
    spin_until(executor, lambda: len(footprints()) == 3, what="the new robot's markers")
    call(SpawnEntity, 'spawn_entity', name='rock', uri='obstacle',
         initial_pose=pose_stamped(6.0, 8.0))
    spin_until(executor, lambda: obstacles and len(obstacles[-1].markers) == 3,
               what="the obstacle's markers")
    body = obstacles[-1].markers[1]
    assert (body.ns, body.header.frame_id) == ('static_obstacle', 'map')
    assert (body.pose.position.x, body.pose.position.y) == (6.0, 8.0)
    assert len(footprints()) == 3
