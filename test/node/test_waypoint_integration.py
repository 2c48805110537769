"""stdr_lite and waypoint_controller together in one process, in simulated time."""

import math

from nav_msgs.msg import Odometry
import pytest
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from ros_helpers import events_executor, overrides, spin_until
from simple_robot_control.pose import yaw_from_quaternion
from simple_robot_control.share import shared_file
from simple_robot_control.validation import ConfigError
from std_msgs.msg import String
from stdr_lite.node.stdr_lite import StdrLite
from waypoint_controller.waypoint_controller import WaypointController
from waypoint_lab.course import in_goal_set
from waypoint_lab.rules import BUNDLED_COURSE
from waypoint_lab.waypoints import load_waypoints

# The lab tour's robot_status in lockstep, as the README shows it: a change made for speed alone
# must leave every line as it is.
LAB_TOUR_STATUS = [
    'STARTED 1.000 2.000 0.00',
    'WAYPOINT 1 3.924 2.063 3.31',
    'WAYPOINT 2 5.936 4.924 85.26',
    'WAYPOINT 3 4.011 7.913 175.17',
    'WAYPOINT 4 2.085 6.011 -94.93',
    'WAYPOINT 5 2.000 3.097 -93.21',
    'WAYPOINT 6 1.072 2.066 -4.90',
    'FINISHED',
]
TRANSIENT = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.TRANSIENT_LOCAL)


class Recorder(Node):
    """Records robot_status and the simulator's own odometry."""

    def __init__(self, context, name='recorder'):
        super().__init__(name, context=context)
        self.status = []
        self.poses = []
        self.create_subscription(String, '/robot_status',
                                 lambda message: self.status.append(message.data), TRANSIENT)
        self.create_subscription(Odometry, '/robot0/odom', self._on_odometry, 100)

    def _on_odometry(self, message):
        pose = message.pose.pose
        self.poses.append((pose.position.x, pose.position.y,
                           yaw_from_quaternion(pose.orientation)))


def run_course(ros_context, executor, course_path, timeout=60.0, simulator_params=(),
               **controller_params):
    """Run a course in lockstep, as fast as it goes; return the controller and the recorder."""
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        lockstep=True, real_time_factor=0.0, **dict(simulator_params)))
    recorder = Recorder(ros_context)
    controller_params.setdefault('use_sim_time', True)
    controller = WaypointController(str(course_path), context=ros_context,
                                    parameter_overrides=overrides(**controller_params))
    for node in (simulator, recorder, controller):
        executor.add_node(node)
    executor.spin_until_future_complete(controller.finished, timeout_sec=timeout)
    assert controller.finished.done(), f'course not done within {timeout} s'
    spin_until(executor, lambda: recorder.status and recorder.status[-1].split()[0] in (
        'FINISHED', 'ABORTED'), what='the last robot_status message')
    return controller, recorder


def parse_pose(message):
    x, y, theta = (float(value) for value in message.split()[-3:])
    return x, y, math.radians(theta)


def test_course_reports_every_waypoint_in_its_goal_set(ros_context, executor, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n4 4 90\n2.5 4 180\n2.5 4 -90\n1.5 3 -135\n')
    controller, recorder = run_course(ros_context, executor, course)
    assert controller.finished.result() == 0
    waypoints = load_waypoints(course)
    kinds = [message.split()[0] for message in recorder.status]
    assert kinds == ['STARTED'] + ['WAYPOINT'] * len(waypoints) + ['FINISHED']
    assert parse_pose(recorder.status[0]) == pytest.approx((1.0, 2.0, 0.0), abs=1e-3)
    for number, message in enumerate(recorder.status[1:-1], start=1):
        assert int(message.split()[1]) == number
        reported = parse_pose(message)
        truth = min(recorder.poses, key=lambda pose: math.dist(pose[:2], reported[:2])
                    + abs(math.remainder(pose[2] - reported[2], math.tau)))
        assert truth == pytest.approx(reported, abs=2e-3)
        assert in_goal_set(truth, waypoints[number - 1])


def test_lockstep_runs_are_identical(ros_context, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 45\n2 3 180\n2 3 -90\n')
    runs = []
    for _ in range(2):
        with events_executor(ros_context) as executor:
            _, recorder = run_course(ros_context, executor, course)
            runs.append(recorder.status)
    assert runs[0][-1] == 'FINISHED'
    assert runs[0] == runs[1]


def test_the_lab_tour_in_lockstep_reports_the_recorded_poses(ros_context, executor):
    _, recorder = run_course(ros_context, executor, shared_file(*BUNDLED_COURSE))
    assert recorder.status == LAB_TOUR_STATUS


def test_late_subscriber_receives_the_whole_run(ros_context, executor, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('2 2 0 2 2 90\n')
    _, recorder = run_course(ros_context, executor, course)
    late = Recorder(ros_context, name='late')
    executor.add_node(late)
    spin_until(executor, lambda: len(late.status) == len(recorder.status),
               what='the replayed robot_status history')
    assert late.status == recorder.status


def test_unreachable_waypoint_is_aborted(ros_context, executor, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('2 2 0\n0.1 5 90\n')
    controller, recorder = run_course(ros_context, executor, course, stall_timeout=2.0)
    assert controller.finished.result() == 1
    assert recorder.status[0].startswith('STARTED ')
    assert recorder.status[1].startswith('WAYPOINT 1 ')
    assert recorder.status[-1].startswith('ABORTED 2 ')
    assert 'FINISHED' not in recorder.status


@pytest.mark.parametrize('text, message', [
    ('1 2 3 4\n', 'course.txt:1: 4 numbers'),
    ('1 2 x\n', "course.txt:1: 'x' is not a number"),
])
def test_bad_course_is_refused_before_anything_moves(ros_context, tmp_path, text, message):
    course = tmp_path / 'course.txt'
    course.write_text(text)
    with pytest.raises(ConfigError, match=message):
        WaypointController(str(course), context=ros_context)


def test_waypoint_file_given_twice_is_refused(ros_context, tmp_path):
    with pytest.raises(ConfigError, match='waypoint file given twice'):
        WaypointController('a.txt', context=ros_context,
                           parameter_overrides=overrides(waypoint_file='b.txt'))


def test_shutting_down_stops_the_robot(ros_context, executor, tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('8 2 0\n')
    simulator = StdrLite(context=ros_context,
                         parameter_overrides=overrides(real_time_factor=20.0))
    recorder = Recorder(ros_context)
    twists = []
    recorder.create_subscription(Odometry, '/robot0/odom',
                                 lambda message: twists.append(message.twist.twist.linear.x), 100)
    controller = WaypointController(str(course), context=ros_context,
                                    parameter_overrides=overrides(use_sim_time=True))
    for node in (simulator, recorder, controller):
        executor.add_node(node)
    spin_until(executor, lambda: twists and twists[-1] > 0.4, what='the robot driving')
    executor.remove_node(controller)
    controller.shut_down()
    controller.destroy_node()
    count = len(twists)
    spin_until(executor, lambda: len(twists) > count + 5, what='odometry after the stop')
    assert twists[-1] == 0.0


@pytest.mark.parametrize('odom_rate_hz', [0.0, 10.0])
def test_stamped_commands_and_slower_odometry_run_a_course(
        ros_context, executor, tmp_path, odom_rate_hz):
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n3 3 90\n')
    controller, recorder = run_course(
        ros_context, executor, course, cmd_vel_stamped=True,
        simulator_params={'cmd_vel_stamped': True, 'odom_rate_hz': odom_rate_hz})
    assert controller.finished.result() == 0
    assert [message.split()[0] for message in recorder.status] == [
        'STARTED', 'WAYPOINT', 'WAYPOINT', 'FINISHED']


def test_a_waypoint_beside_a_wall_facing_away_is_reached_off_the_wall(ros_context, executor,
                                                                      tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('0.8 3 90\n0.75 2.5 0\n')
    controller, recorder = run_course(ros_context, executor, course)
    assert controller.finished.result() == 0
    wall_side = 0.35 + 0.2
    assert min(x for x, _, _ in recorder.poses) > wall_side
