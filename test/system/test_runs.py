"""Runs across processes: nothing is lost, nothing drives blind, nothing goes unnoticed."""

import re
import signal
import time

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from processes import run, start_logged, stop, wait_for_text
import pytest
from rclpy.node import Node
from ros_helpers import spin_until
from simple_robot_control.graph import UNNAMED

from waypoint_lab.runner import NEWCOMER_FOR

REPEATS = 3


@pytest.fixture
def simulator(tmp_path):
    """Run stdr_lite free at ten times real time; give its log file."""
    log = tmp_path / 'stdr_lite.log'
    process = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=10.0', log=log)
    wait_for_text(log, 'real_time_factor', process)
    yield process, log
    if process.poll() is None:
        assert stop(process, signal.SIGINT)[0] == 0


def test_a_short_run_reaches_a_subscriber_that_was_there_first(tmp_path, simulator, ros_context):
    course = tmp_path / 'course.txt'
    course.write_text('1.3 2 0\n')
    watcher = Node('watcher', context=ros_context)
    for attempt in range(REPEATS):
        log = tmp_path / f'monitor{attempt}.log'
        monitor = start_logged('course_monitor', str(course), log=log)
        deadline = time.monotonic() + 20.0
        while watcher.count_subscribers('/robot_status') == 0:
            assert time.monotonic() < deadline, 'course_monitor never subscribed'
            time.sleep(0.05)
        controller = run('waypoint_controller', str(course), timeout=60)
        assert controller.returncode == 0, controller.stderr
        assert monitor.wait(timeout=20) == 0, log.read_text()
        assert log.read_text().splitlines()[-2:][0] == 'FINISHED'
    watcher.destroy_node()


def test_a_second_controller_on_the_same_robot_is_refused(tmp_path):
    log = tmp_path / 'first.log'
    first = start_logged('waypoint_controller', log=log)
    try:
        wait_for_text(log, 'following', first)
        time.sleep(NEWCOMER_FOR + 1.0)
        second = run('waypoint_controller', timeout=30)
    finally:
        assert stop(first, signal.SIGINT)[0] == 0
    assert second.returncode == 2
    lines = second.stderr.strip().splitlines()
    # Discovery may have brought the first controller's publisher before its node's name.
    assert lines[-1] in (f'waypoint_controller: error: {name} already publishes on '
                         '/robot0/cmd_vel: one robot takes commands from one node; stop it or '
                         'give robot_name' for name in ('/waypoint_controller', UNNAMED))
    assert 'Traceback' not in second.stderr


def test_a_restarted_simulator_stops_the_controller(tmp_path, simulator):
    process, _ = simulator
    course = tmp_path / 'course.txt'
    # About 270 s of driving, 27 s of wall time: the run is still on when the simulator restarts,
    # however long the second one takes to start (90 s of driving ended first once, beside two
    # busy loops and the suite's workers).
    course.write_text('15 2 0\n15 12 90\n2 12 180\n2 3 270\n' * 3)
    log = tmp_path / 'controller.log'
    controller = start_logged('waypoint_controller', str(course), log=log)
    wait_for_text(log, 'STARTED', controller)
    time.sleep(2.0)
    # The new simulator is up, paused, before the old one goes: however slow its start, the
    # robot's odometry keeps a publisher, and the clock goes back when it plays. It plays at
    # real time, so that the command it holds moves the robot only for the wall time the stop
    # takes to come (at ten times real time, 50 ms of a loaded machine were 5 cm).
    restarted = start_logged('stdr_lite', '--ros-args', '-p', 'paused:=true',
                             log=tmp_path / 'restarted.log')
    try:
        wait_for_text(tmp_path / 'restarted.log', 'real_time_factor', restarted)
        assert stop(process, signal.SIGINT)[0] == 0
        assert run('stdr_ctl', 'play').returncode == 0
        assert controller.wait(timeout=30) == 1
    finally:
        stop(restarted, signal.SIGINT)
    output = log.read_text()
    assert 'went back' in output and 'the simulator restarted; stopping the robot' in output
    # Reported at the new simulator's robot, where it starts: the held command moves it for as
    # long as the stop takes to come, a step or two (at most 1 rad/s: 1.15 degrees a step).
    aborted = r'ABORTED (?:[1-9]|1[0-2]) 1\.0[0-4]\d 2\.000 -?[0-2]\.\d\d\n'
    assert re.search(aborted, output), output


def test_the_controller_names_the_remapped_topic_while_odometry_is_absent(tmp_path):
    log = tmp_path / 'controller.log'
    controller = start_logged('waypoint_controller', '--ros-args', '-r',
                              '/robot0/odom:=/elsewhere/odom', log=log)
    try:
        wait_for_text(log, 'no odometry on /elsewhere/odom for 3 s: is stdr_lite running?',
                      controller, timeout=10.0)
    finally:
        assert stop(controller, signal.SIGINT)[0] == 0


def test_the_simulator_warns_when_two_nodes_command_one_robot(simulator, ros_context, executor):
    _, log = simulator
    publishers = []
    for name in ('teleop', 'script'):
        node = Node(name, context=ros_context)
        executor.add_node(node)
        publishers.append(node.create_publisher(Twist, '/robot0/cmd_vel', 10))
    wait_for_text(log, '/robot0/cmd_vel has 2 publishers (/script, /teleop): their commands '
                  'mix', timeout=10.0)


def test_ctrl_c_stops_the_robot_it_drives(tmp_path, simulator, ros_context, executor):
    course = tmp_path / 'course.txt'
    course.write_text('15 2 0\n')
    speeds = []
    watcher = Node('watcher', context=ros_context)
    watcher.create_subscription(Odometry, '/robot0/odom',
                                lambda message: speeds.append(message.twist.twist.linear.x), 10)
    executor.add_node(watcher)
    controller = start_logged('waypoint_controller', str(course), log=tmp_path / 'c.log')
    spin_until(executor, lambda: speeds and speeds[-1] > 0.4, timeout=30.0,
               what='the robot driving')
    assert stop(controller, signal.SIGINT)[0] == 0
    count = len(speeds)
    spin_until(executor, lambda: len(speeds) > count + 20, what='odometry after the stop')
    assert speeds[-1] == 0.0
