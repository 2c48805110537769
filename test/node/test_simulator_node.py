"""The stdr_lite node in-process: commands in, odometry, map and clock out."""

import functools
import math

from geometry_msgs.msg import Pose2D, PoseWithCovarianceStamped, Twist
from nav_msgs.msg import MapMetaData, OccupancyGrid, Odometry
from nav_msgs.srv import GetMap
import pytest
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.time import Time
from ros_helpers import (overrides, pose_stamped, ServiceCaller, spin_for, spin_until,
                         wait_for_subscribers)
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan, Range
from simple_robot_control.pose import yaw_from_quaternion
from simple_robot_control.validation import ConfigError
from simulation_interfaces.msg import Result, SimulationState
from simulation_interfaces.srv import DeleteEntity, SetSimulationState, SpawnEntity
from std_msgs.msg import Bool
from stdr_lite.node.stdr_lite import StdrLite
from stdr_msgs.srv import MoveRobot


class Probe(Node):
    """Commands robot0 and records what the simulator publishes."""

    def __init__(self, context):
        super().__init__('probe', context=context)
        self.odometry = []
        self.clock = []
        self.cmd_vel = self.create_publisher(Twist, '/robot0/cmd_vel', 10)
        self.create_subscription(Odometry, '/robot0/odom', self.odometry.append, 100)
        self.create_subscription(Clock, '/clock', self.clock.append, 100)

    def command(self, executor, linear, angular=0.0):
        wait_for_subscribers(executor, self.cmd_vel)
        message = Twist()
        message.linear.x, message.angular.z = linear, angular
        self.cmd_vel.publish(message)

    def applied(self, linear, angular=0.0):
        return [odometry for odometry in self.odometry
                if odometry.twist.twist.linear.x == linear
                and odometry.twist.twist.angular.z == angular]


def start(ros_context, executor, **params):
    params.setdefault('real_time_factor', 0.0)
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(**params))
    probe = Probe(ros_context)
    executor.add_node(simulator)
    executor.add_node(probe)
    return simulator, probe


def consecutive(messages):
    stamps = [Time.from_msg(message.header.stamp).nanoseconds for message in messages]
    return [(a, b) for a, b, ta, tb in zip(messages, messages[1:], stamps, stamps[1:])
            if tb - ta == 20_000_000]


def test_twist_moves_the_robot_by_equation_2_each_step(ros_context, executor):
    _, probe = start(ros_context, executor, initial_pose=[2.0, 3.0, 0.5])
    probe.command(executor, 0.8, 0.3)
    spin_until(executor, lambda: len(consecutive(probe.applied(0.8, 0.3))) >= 5,
               what='odometry with the command applied')
    for before, after in consecutive(probe.applied(0.8, 0.3)):
        theta = yaw_from_quaternion(before.pose.pose.orientation)
        dx = after.pose.pose.position.x - before.pose.pose.position.x
        dy = after.pose.pose.position.y - before.pose.pose.position.y
        assert (dx, dy) == pytest.approx((0.016 * math.cos(theta), 0.016 * math.sin(theta)))
        assert yaw_from_quaternion(after.pose.pose.orientation) == pytest.approx(theta + 0.006)
    first = probe.odometry[0]
    assert (first.header.frame_id, first.child_frame_id) == ('robot0/odom', 'robot0/base_link')


def test_speeds_are_clamped_to_the_limits(ros_context, executor):
    _, probe = start(ros_context, executor, max_linear_speed=0.5, max_angular_speed=1.0)
    probe.command(executor, 10.0, -10.0)
    spin_until(executor, lambda: probe.applied(0.5, -1.0), what='clamped command')


def test_non_finite_command_is_ignored(ros_context, executor):
    _, probe = start(ros_context, executor)
    probe.command(executor, 0.4)
    spin_until(executor, lambda: probe.applied(0.4), what='first command')
    probe.command(executor, math.nan, 0.2)
    probe.command(executor, 0.0, 0.1)
    spin_until(executor, lambda: probe.applied(0.0, 0.1), what='the command after NaN')
    index = probe.odometry.index(probe.applied(0.0, 0.1)[0])
    before = probe.odometry[:index]
    assert all(odometry.twist.twist.linear.x == 0.4 for odometry in before[-3:])
    assert all(math.isfinite(odometry.pose.pose.position.x) for odometry in probe.odometry)


def test_stale_command_times_out(ros_context, executor):
    _, probe = start(ros_context, executor, cmd_vel_timeout=0.2)
    probe.command(executor, 0.4)
    spin_until(executor, lambda: probe.applied(0.4), what='the command')
    moving = probe.applied(0.4)
    spin_until(executor, lambda: probe.odometry[-1].twist.twist.linear.x == 0.0,
               what='the timeout')
    duration = (Time.from_msg(probe.odometry[-1].header.stamp)
                - Time.from_msg(moving[0].header.stamp)).nanoseconds
    assert 0.2e9 <= duration <= 0.24e9


def test_clock_advances_one_step_at_a_time(ros_context, executor):
    _, probe = start(ros_context, executor, rate_hz=40.0)
    spin_until(executor, lambda: len(probe.clock) >= 20, what='clock messages')
    stamps = [Time.from_msg(message.clock).nanoseconds for message in probe.clock]
    steps = {b - a for a, b in zip(stamps, stamps[1:])}
    assert steps <= {25_000_000 * k for k in range(1, 1000)}
    assert stamps == sorted(stamps) and stamps[-1] > stamps[0]


def stamps(messages):
    return [Time.from_msg(message.header.stamp).nanoseconds for message in messages]


def test_lockstep_holds_time_until_the_odometry_is_answered(ros_context, executor):
    simulator, probe = start(ros_context, executor, lockstep=True)
    spin_until(executor, lambda: probe.odometry, what='the first odometry')
    spin_for(executor, 0.3)
    assert set(stamps(probe.odometry)) == {0}
    assert simulator.sim_time == 0.0


def test_lockstep_takes_one_step_per_answer(ros_context, executor):
    simulator, probe = start(ros_context, executor, lockstep=True)
    answers = 25
    answered = []
    forward = Twist()
    forward.linear.x = 0.5

    def answer(odometry):
        stamp = Time.from_msg(odometry.header.stamp).nanoseconds
        if len(answered) < answers and stamp not in answered:
            answered.append(stamp)
            probe.cmd_vel.publish(forward)

    probe.create_subscription(Odometry, '/robot0/odom', answer, 100)
    spin_until(executor, lambda: len(answered) == answers, what='the answered odometry')
    spin_for(executor, 0.3)
    steps = sorted(set(stamps(probe.odometry)))
    assert steps == [20_000_000 * k for k in range(answers + 1)]
    assert simulator.sim_time == pytest.approx(answers * 0.02)
    last = probe.odometry[-1]
    assert last.pose.pose.position.x == pytest.approx(1.0 + answers * 0.5 * 0.02)


def test_the_stall_flag_says_when_a_wall_refuses_the_robot(ros_context, executor):
    _, probe = start(ros_context, executor, initial_pose=[18.5, 2.0, 0.0], real_time_factor=5.0)
    stalls = []
    probe.create_subscription(Bool, '/robot0/stall', lambda flag: stalls.append(flag.data), 100)
    spin_until(executor, lambda: stalls, what='the stall flag')
    assert not any(stalls), 'standing still is no stall'
    probe.command(executor, 1.0)
    spin_until(executor, lambda: stalls[-5:] == [True] * 5, what='a stall at the wall')
    assert probe.odometry[-1].twist.twist.linear.x == 0.0
    probe.command(executor, -1.0)
    spin_until(executor, lambda: stalls[-1] is False, what='driving away from the wall')


@pytest.mark.parametrize('lockstep', [False, True])
def test_a_simulator_started_paused_publishes_nothing_until_played(ros_context, executor,
                                                                   lockstep):
    simulator, probe = start(ros_context, executor, paused=True, lockstep=lockstep,
                             real_time_factor=1.0)
    spin_for(executor, 1.0)
    assert not probe.odometry and not probe.clock and simulator.sim_time == 0.0
    call = ServiceCaller(executor, probe)
    playing = SimulationState(state=SimulationState.STATE_PLAYING)
    assert call(SetSimulationState, 'set_simulation_state', state=playing).result.result == (
        Result.RESULT_OK)
    spin_until(executor, lambda: probe.odometry, what='odometry once played')
    assert stamps(probe.odometry)[0] == (0 if lockstep else 20_000_000)


def latched_message(ros_context, executor, message_type, topic):
    """Return the first message a late reader (reliable, transient local) gets on topic."""
    received = []
    late = Node('late', context=ros_context)
    executor.add_node(late)
    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
    late.create_subscription(message_type, topic, received.append, latched)
    spin_until(executor, lambda: received, what=topic)
    return late, received[0]


def test_late_subscriber_receives_the_map(ros_context, executor):
    start(ros_context, executor)
    _, grid = latched_message(ros_context, executor, OccupancyGrid, '/map')
    assert (grid.info.width, grid.info.height) == (400, 300)
    assert grid.info.resolution == pytest.approx(0.05)
    assert len(grid.data) == 400 * 300 and grid.data[0] == 100 and grid.data[150 * 400 + 200] == 0
    assert grid.header.frame_id == 'map'


def test_a_hidden_map_gives_its_geometry_alone(ros_context, executor):
    """map_visible false: /map_metadata (latched), no /map; GetMap's cells all unknown."""
    start(ros_context, executor, map_visible=False)
    late, info = latched_message(ros_context, executor, MapMetaData, '/map_metadata')
    assert (info.width, info.height) == (400, 300) and info.resolution == pytest.approx(0.05)
    assert late.count_publishers('/map') == 0
    for service in ('static_map', 'map_server/map'):
        grid = ServiceCaller(executor, late, prefix='')(GetMap, service).map
        assert (grid.info.width, grid.info.height, grid.header.frame_id) == (400, 300, 'map')
        assert len(grid.data) == 400 * 300 and set(grid.data) == {-1}


@pytest.mark.parametrize('params, message', [
    ({'map_yaml': '/nonexistent/world.yaml'}, '/nonexistent/world.yaml: cannot read map file'),
    ({'initial_pose': [0.1, 5.0, 0.0]}, 'touches a wall'),
    ({'initial_pose': [30.0, 5.0, 0.0]}, 'off the map'),
    ({'initial_pose': [1.0, 2.0]}, 'initial_pose must be [x, y, theta]'),
    ({'rate_hz': 0.0}, 'rate_hz must be in [1, 1000], got 0'),
    ({'integrator': 'rk4'}, "integrator must be one of euler, arc, got 'rk4'"),
    ({'rate_hz': 'fast'}, 'parameter rate_hz'),
    ({'rate_hz': 5000}, 'rate_hz must be in [1, 1000], got 5000'),
    ({'rate_hz': 50.0, 'rate_hz_': 1.0},
     "unknown parameter 'rate_hz_' for stdr_lite; did you mean rate_hz?"),
    ({'robots_file': '/no/robots.yaml'}, '/no/robots.yaml: cannot read robot list'),
    ({'robot_description': '/no/robot.yaml'}, '/no/robot.yaml: cannot read robot file'),
    ({'robots_file': 'ROBOTS', 'robot_name': 'solo'}, 'robots_file lists the robots; drop '
     'robot_name'),
    ({'robots_file': 'CROWDED'}, 'robot1 in '),
])
def test_bad_configuration_is_one_clear_error(ros_context, tmp_path, params, message):
    lists = {'ROBOTS': 'robots:\n  - {}\n',
             'CROWDED': 'robots:\n  - {pose: [3, 3, 0]}\n  - {pose: [3.2, 3, 0]}\n'}
    for key, value in params.items():
        if isinstance(value, str) and value in lists:
            path = tmp_path / f'{value.lower()}.yaml'
            path.write_text(lists[value])
            params[key] = str(path)
    with pytest.raises(ConfigError) as raised:
        StdrLite(context=ros_context, parameter_overrides=overrides(**params))
    assert message in str(raised.value)
    assert '\n' not in str(raised.value)


def test_a_node_that_cannot_start_leaves_nothing_on_the_graph(ros_context):
    """Its DDS entities are destroyed at once, not by the garbage collector at any moment."""
    watcher = Node('watcher', context=ros_context)
    try:
        with pytest.raises(ConfigError):
            StdrLite(context=ros_context, parameter_overrides=overrides(rate_hz=-1.0))
        assert 'stdr_lite' not in watcher.get_node_names()
    finally:
        watcher.destroy_node()


def pose_message(x, y, theta):
    message = PoseWithCovarianceStamped()
    message.header.frame_id = 'map'
    message.pose.pose.position.x, message.pose.pose.position.y = x, y
    message.pose.pose.orientation.z = math.sin(0.5 * theta)
    message.pose.pose.orientation.w = math.cos(0.5 * theta)
    return message


def latest_poses(node, names):
    """Subscribe to each robot's odometry; return a dict that keeps the latest (x, y, theta)."""
    latest = {}

    def remember(name, message):
        pose = message.pose.pose
        latest[name] = (pose.position.x, pose.position.y, yaw_from_quaternion(pose.orientation))

    for name in names:
        node.create_subscription(Odometry, f'/{name}/odom', functools.partial(remember, name),
                                 10)
    return latest


def test_robot_list_teleport_and_refusal(ros_context, executor, tmp_path):
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots:\n  - {pose: [2.0, 2.0, 0.0]}\n  - {name: scout, pose: [4.0, 2.0, '
                      '3.14]}\n')
    _, probe = start(ros_context, executor, robots_file=str(robots))
    latest = latest_poses(probe, ['robot0', 'scout'])
    spin_until(executor, lambda: len(latest) == 2, what='odometry of both robots')
    teleport = probe.create_publisher(PoseWithCovarianceStamped, '/scout/initialpose', 10)
    wait_for_subscribers(executor, teleport)
    teleport.publish(pose_message(2.2, 2.1, 1.0))
    spin_for(executor, 0.3)
    assert latest['scout'] == pytest.approx((4.0, 2.0, 3.14))
    teleport.publish(pose_message(6.0, 5.0, 1.0))
    spin_until(executor, lambda: latest['scout'] == pytest.approx((6.0, 5.0, 1.0)),
               what='the teleported robot')
    assert latest['robot0'] == pytest.approx((2.0, 2.0, 0.0))


def test_stdrs_replace_teleports_and_refuses_a_wall(ros_context, executor):
    """The teleport of STDR's /robotN/replace (stdr_msgs/srv/MoveRobot), as scripts call it."""
    _, probe = start(ros_context, executor)
    latest = latest_poses(probe, ['robot0'])
    spin_until(executor, lambda: 'robot0' in latest, what='odometry')
    replace = ServiceCaller(executor, probe, prefix='/robot0')
    replace(MoveRobot, 'replace', new_pose=Pose2D(x=0.1, y=5.0, theta=0.0))
    spin_for(executor, 0.3)
    assert latest['robot0'] == pytest.approx((1.0, 2.0, 0.0)), 'into the wall: refused'
    replace(MoveRobot, 'replace', new_pose=Pose2D(x=6.0, y=5.0, theta=1.0))
    spin_until(executor, lambda: latest['robot0'] == pytest.approx((6.0, 5.0, 1.0)),
               what='the replaced robot')


def test_robots_come_and_go_while_running(ros_context, executor):
    simulator, probe = start(ros_context, executor)
    call = ServiceCaller(executor, probe)
    latest = latest_poses(probe, ['scout'])
    spawned = call(SpawnEntity, 'spawn_entity', name='scout', uri='lab_robot',
                   initial_pose=pose_stamped(5.0, 5.0, 0.5))
    assert (spawned.result.result, spawned.entity_name) == (Result.RESULT_OK, 'scout')
    spin_until(executor, lambda: 'scout' in latest, what="the new robot's odometry")
    assert latest['scout'] == pytest.approx((5.0, 5.0, 0.5))
    assert call(DeleteEntity, 'delete_entity', entity='scout').result.result == Result.RESULT_OK
    spin_until(executor, lambda: probe.count_publishers('/scout/odom') == 0,
               what='the removal')
    assert probe.count_publishers('/robot0/odom') == 1


def test_laser_and_sonars_are_published_with_their_frames(ros_context, executor):
    start(ros_context, executor, initial_pose=[3.0, 7.5, math.pi])
    scans, ranges = [], []
    listener = Node('listener', context=ros_context)
    executor.add_node(listener)
    listener.create_subscription(LaserScan, '/robot0/laser_0', scans.append, 10)
    listener.create_subscription(Range, '/robot0/sonar_0', ranges.append, 10)
    spin_until(executor, lambda: len(scans) >= 2 and ranges, what='laser and sonar readings')
    scan = scans[-1]
    assert scan.header.frame_id == 'robot0/laser_0' and len(scan.ranges) == 667
    assert (scan.range_min, scan.range_max) == pytest.approx((0.06, 4.09))
    middle = scan.ranges[333]
    assert middle == pytest.approx(3.0 - 0.1 - 0.35, abs=0.06)
    stamps = [Time.from_msg(message.header.stamp).nanoseconds for message in scans]
    assert stamps[1] - stamps[0] == 100_000_000
    sonar = ranges[-1]
    assert sonar.header.frame_id == 'robot0/sonar_0'
    assert sonar.radiation_type == Range.ULTRASOUND
    assert sonar.range == pytest.approx(3.0 - 0.15 - 0.35, abs=0.1)
