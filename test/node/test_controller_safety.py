"""The controller never drives blind: a restarted simulator, a second controller, bad values."""

from geometry_msgs.msg import Twist
from nav_msgs.msg import OccupancyGrid, Odometry
import pytest
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from ros_helpers import overrides, spin_for, spin_until, wait_for_subscribers
from simple_robot_control.pose import set_pose
from simple_robot_control.validation import ConfigError
from std_msgs.msg import String
from stdr_lite.node.stdr_lite import StdrLite
from waypoint_controller.waypoint_controller import WaypointController
from waypoint_lab.runner import FIRST_ANSWER_AFTER, NEWCOMER_FOR

EVERYTHING = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.TRANSIENT_LOCAL)


class FakeSimulator(Node):
    """Publishes odometry stamps of its choosing and records the commands it gets."""

    def __init__(self, context):
        super().__init__('fake_simulator', context=context)
        self.commands, self.status = [], []
        self.odometry = self.create_publisher(Odometry, '/robot0/odom', 10)
        self.create_subscription(Twist, '/robot0/cmd_vel', self.commands.append, 10)
        self.create_subscription(String, '/robot_status',
                                 lambda message: self.status.append(message.data), EVERYTHING)

    def send(self, executor, seconds, x=1.0):
        wait_for_subscribers(executor, self.odometry)
        message = Odometry()
        stamp = message.header.stamp
        stamp.sec, stamp.nanosec = divmod(round(seconds * 1e9), 1_000_000_000)
        set_pose(message.pose.pose, x, 2.0, 0.0)
        count = len(self.commands)
        self.odometry.publish(message)
        spin_until(executor, lambda: len(self.commands) > count, what='the answer')
        return self.commands[-1]


def test_odometry_time_going_back_stops_the_robot_and_ends_the_run(ros_context, executor,
                                                                   tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('8 2 0\n')
    simulator = FakeSimulator(ros_context)
    controller = WaypointController(str(course), context=ros_context)
    executor.add_node(simulator)
    executor.add_node(controller)
    for step in range(1, 30):
        driving = simulator.send(executor, 10.0 + 0.05 * step, x=1.0 + 0.025 * step)
    assert driving.linear.x > 0.0
    restarted = simulator.send(executor, 0.02)
    assert (restarted.linear.x, restarted.angular.z) == (0.0, 0.0)
    assert controller.finished.done() and controller.finished.result() == 1
    spin_until(executor, lambda: simulator.status[-1:] == ['ABORTED 1 1.000 2.000 0.00'],
               what='ABORTED')
    count = len(simulator.commands)
    simulator.odometry.publish(Odometry())
    executor.spin_once(timeout_sec=0.2)
    assert len(simulator.commands) == count


def test_the_first_answer_waits_for_a_published_map(ros_context, executor, tmp_path):
    """A map that comes late would change the first plans: the run must not depend on it."""
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n')
    simulator = FakeSimulator(ros_context)
    map_publisher = simulator.create_publisher(OccupancyGrid, '/map', EVERYTHING)
    controller = WaypointController(str(course), context=ros_context)
    executor.add_node(simulator)
    executor.add_node(controller)
    wait_for_subscribers(executor, simulator.odometry)
    wait_for_subscribers(executor, map_publisher)
    message = Odometry()
    message.header.stamp.sec = 1
    set_pose(message.pose.pose, 1.0, 2.0, 0.0)
    simulator.odometry.publish(message)
    spin_for(executor, FIRST_ANSWER_AFTER + 1.0)
    assert simulator.commands == []
    grid = OccupancyGrid()
    grid.info.resolution, grid.info.width, grid.info.height = 0.1, 60, 40
    grid.data = [0] * (60 * 40)
    map_publisher.publish(grid)
    spin_until(executor, lambda: simulator.commands, what='the first answer')
    assert simulator.commands[0].linear.x > 0.0


def test_a_second_controller_on_one_robot_refuses_to_start(ros_context, executor, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n')
    first = WaypointController(str(course), context=ros_context)
    executor.add_node(first)
    executor.spin_until_future_complete(first.finished, timeout_sec=NEWCOMER_FOR + 0.5)
    second = WaypointController(str(course), context=ros_context)
    executor.add_node(second)
    spin_until(executor, second.finished.done, what='the refusal')
    error = second.finished.exception()
    assert isinstance(error, ConfigError)
    assert str(error).startswith('/waypoint_controller already publishes on /robot0/cmd_vel')
    assert not first.finished.done()


def test_another_robot_may_have_its_own_controller(ros_context, executor, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n')
    first = WaypointController(str(course), context=ros_context)
    other = WaypointController(str(course), context=ros_context,
                               parameter_overrides=overrides(robot_name='robot1'))
    for node in (first, other):
        executor.add_node(node)
    executor.spin_until_future_complete(other.finished, timeout_sec=NEWCOMER_FOR + 0.5)
    assert not other.finished.done() and not first.finished.done()


@pytest.mark.parametrize('name, value, message', [
    ('angle_tolerance_deg', -5.0, 'angle_tolerance_deg must be in (0, 180], got -5'),
    ('distance_tolerance', float('inf'), 'distance_tolerance must be in (0, 10], got inf'),
    ('max_linear_speed', float('inf'), 'max_linear_speed must be in (0, 10], got inf'),
    ('robot_name', 'robé', 'robot_name must be a ROS name'),
])
def test_bad_values_are_named_in_the_users_units(ros_context, name, value, message):
    with pytest.raises(ConfigError) as raised:
        WaypointController(context=ros_context, parameter_overrides=overrides(**{name: value}))
    assert str(raised.value).startswith(message)


def test_an_abort_names_a_far_waypoint_compactly(ros_context, executor, tmp_path, capfd):
    course = tmp_path / 'course.txt'
    course.write_text('1e6 2 0\n')
    simulator = StdrLite(context=ros_context,
                         parameter_overrides=overrides(lockstep=True, real_time_factor=0.0))
    controller = WaypointController(str(course), context=ros_context,
                                    parameter_overrides=overrides(stall_timeout=1.0))
    for node in (simulator, controller):
        executor.add_node(node)
    executor.spin_until_future_complete(controller.finished, timeout_sec=60.0)
    assert controller.finished.result() == 1
    assert 'unreachable: no progress for 1 s, still 1e+06 m away' in capfd.readouterr().err


@pytest.mark.parametrize('width, height, values, resolution', [
    (100000, 100000, 0, 0.05), (60, 40, 100, 0.05), (60, 40, 2400, 0.0),
    (60, 40, 2400, float('nan'))])
def test_a_malformed_map_is_ignored_and_the_run_goes_on(ros_context, executor, tmp_path, capfd,
                                                        width, height, values, resolution):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n')
    simulator = FakeSimulator(ros_context)
    map_publisher = simulator.create_publisher(OccupancyGrid, '/map', EVERYTHING)
    grid = OccupancyGrid()
    grid.info.resolution, grid.info.width, grid.info.height = resolution, width, height
    grid.data = [0] * values
    map_publisher.publish(grid)
    controller = WaypointController(str(course), context=ros_context)
    executor.add_node(simulator)
    executor.add_node(controller)
    wait_for_subscribers(executor, map_publisher)
    driving = simulator.send(executor, 1.0)
    assert driving.linear.x > 0.0
    assert not controller.finished.done()
    assert 'ignoring /map: ' in capfd.readouterr().err


def lockstep_run(ros_context, executor, tmp_path, **simulator_parameters):
    course = tmp_path / 'course.txt'
    course.write_text('8 2 0\n')
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        lockstep=True, real_time_factor=0.0, **simulator_parameters))
    controller = WaypointController(str(course), context=ros_context)
    for node in (simulator, controller):
        executor.add_node(node)
    spin_until(executor, lambda: simulator.simulation.pose('robot0')[0] > 2.0, timeout=30.0,
               what='the robot under way')
    return simulator, controller


def test_a_reset_of_the_robot_under_a_lockstep_run_ends_it_in_a_clear_line(
        ros_context, executor, tmp_path, capfd):
    """The reset keeps the clock: lockstep steps on into it, and the controller sees the jump."""
    simulator, controller = lockstep_run(ros_context, executor, tmp_path)
    steps = simulator.simulation.step_count
    simulator.simulation.reset(time=False, state=True, spawned=True)
    for _ in simulator.restart(new_time=False):
        pass
    executor.spin_until_future_complete(controller.finished, timeout_sec=10.0)
    assert controller.finished.result() == 1
    assert simulator.simulation.step_count > steps
    assert 'it was moved (a teleport, or a reset of the simulation)' in capfd.readouterr().err


def test_a_deleted_robot_ends_its_run(ros_context, executor, tmp_path, capfd):
    simulator, controller = lockstep_run(ros_context, executor, tmp_path)
    simulator.simulation.remove('robot0')
    simulator.sync_entities()
    executor.spin_until_future_complete(controller.finished, timeout_sec=15.0)
    assert controller.finished.result() == 1
    assert 'it has no publisher any more: the robot was deleted' in capfd.readouterr().err
