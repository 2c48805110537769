"""
cmd_vel's message type across processes: the simulator follows its publishers or names them.

A process holds one DDS participant, in which one topic has one type: the publishers of the
two velocity types and the simulator run in processes of their own.
"""

import signal
import subprocess

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from processes import run, start, start_logged, stop, wait_for_text
import pytest
from rclpy.node import Node
from ros_helpers import spin_until
from simple_robot_control.graph import MISMATCH_PATIENCE, UNNAMED


@pytest.fixture
def simulator(tmp_path):
    """Run stdr_lite reading geometry_msgs/Twist (its default); give its log file."""
    log = tmp_path / 'stdr_lite.log'
    process = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=5.0', log=log)
    wait_for_text(log, 'real_time_factor', process)
    yield log
    assert stop(process, signal.SIGINT)[0] == 0


def says_it_follows(log_text, kind, node):
    """
    Tell whether the simulator's log says it took kind from node.

    Discovery may bring a publisher before its node's name: the line then says so.
    """
    return any(f'/robot0/cmd_vel: now read as {kind}, the type of its publishers ({name} sends '
               f'{kind})' in log_text for name in (node, UNNAMED))


def test_a_twist_stamped_publisher_drives_a_robot_configured_for_twist(simulator, ros_context,
                                                                       executor):
    teleop = Node('teleop', context=ros_context)
    odometry = []
    teleop.create_subscription(Odometry, '/robot0/odom', odometry.append, 10)
    publisher = teleop.create_publisher(TwistStamped, '/robot0/cmd_vel', 10)
    command = TwistStamped()
    command.twist.linear.x = 0.4
    teleop.create_timer(0.1, lambda: publisher.publish(command))
    executor.add_node(teleop)
    spin_until(executor, lambda: odometry and odometry[-1].twist.twist.linear.x == 0.4,
               timeout=20.0, what='the robot driven by stamped commands')
    assert says_it_follows(simulator.read_text(), 'geometry_msgs/msg/TwistStamped', '/teleop')


def test_publishers_of_both_types_are_named(simulator, ros_context):
    plain = Node('plain_teleop', context=ros_context)
    plain.create_publisher(Twist, '/robot0/cmd_vel', 10)
    stamped = start('move_robot', '--ros-args', '-p', 'cmd_vel_stamped:=true', '-r',
                    '__node:=stamped_teleop', stdin=subprocess.PIPE)
    try:
        warning = wait_for_text(simulator, 'publishers disagree', timeout=20.0)
    finally:
        stamped.kill()
        stamped.communicate()
        plain.destroy_node()
    line = next(line for line in warning.splitlines() if 'publishers disagree' in line)
    # Discovery may bring the other process's publisher before its node's name.
    assert any(f'(/plain_teleop sends geometry_msgs/msg/Twist, {name} sends '
               'geometry_msgs/msg/TwistStamped)' in line for name in ('/stamped_teleop', UNNAMED))
    assert line.endswith('it is read as geometry_msgs/msg/Twist, so only those commands drive '
                         'the robot')


def test_a_simulator_reading_stamped_commands_follows_a_controller_sending_twist(tmp_path):
    log = tmp_path / 'stdr_lite.log'
    simulator = start_logged('stdr_lite', '--ros-args', '-p', 'cmd_vel_stamped:=true', '-p',
                             'real_time_factor:=5.0', log=log)
    try:
        wait_for_text(log, 'real_time_factor', simulator)
        course = tmp_path / 'course.txt'
        course.write_text('3 2 0\n')
        result = run('waypoint_controller', str(course), timeout=60)
        assert result.returncode == 0, result.stderr
        content = wait_for_text(log, '/robot0/cmd_vel: now read as geometry_msgs/msg/Twist,')
        assert says_it_follows(content, 'geometry_msgs/msg/Twist', '/waypoint_controller')
    finally:
        assert stop(simulator, signal.SIGINT)[0] == 0


def test_a_controller_stops_when_cmd_vel_is_read_as_another_type_for_good(tmp_path,
                                                                          ros_context, executor):
    reader = Node('stubborn_simulator', context=ros_context)
    reader.create_subscription(TwistStamped, '/robot0/cmd_vel', lambda message: None, 10)
    executor.add_node(reader)
    course = tmp_path / 'course.txt'
    course.write_text('3 2 0\n')
    result = run('waypoint_controller', str(course), timeout=30 + MISMATCH_PATIENCE)
    assert result.returncode == 2
    assert ('waypoint_controller: error: /robot0/cmd_vel is read as '
            'geometry_msgs/msg/TwistStamped by /stubborn_simulator, but this node sends '
            'geometry_msgs/msg/Twist') in result.stderr
