"""The Python API and the node are one simulation: the same commands give the same poses."""

import math
from pathlib import Path
import re

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
import numpy as np
import pytest
from rclpy.time import Time
from ros_helpers import simulator_and_client, spin_until
from sensor_msgs.msg import LaserScan
from simple_robot_control.pose import pose_from_message
from std_msgs.msg import String
from stdr_lite import load_world, SimulationSettings
from waypoint_lab.learning.arena import Arena
from waypoint_lab.learning.policy_controller import PolicyController, scan_at
from waypoint_lab.learning.task import observe, TaskSettings

STEPS = 120


def command_at(step):
    """Return step's command: turns and reverses, then a push into the left wall."""
    return (-1.5 if step > 80 else 0.8 * math.sin(step / 9.0), 1.2 * math.cos(step / 13.0))


def test_a_lockstep_run_through_the_node_is_the_apis_run(ros_context, executor):
    simulator, client = simulator_and_client(ros_context, executor, lockstep=True,
                                             real_time_factor=0.0,
                                             initial_pose=[1.0, 2.0, 0.3])
    commands = client.create_publisher(Twist, '/robot0/cmd_vel', 10)
    poses = {}

    def answer(message):
        stamp = Time.from_msg(message.header.stamp).nanoseconds
        if stamp in poses or len(poses) > STEPS:
            return
        poses[stamp] = pose_from_message(message.pose.pose)
        twist = Twist()
        twist.linear.x, twist.angular.z = command_at(len(poses) - 1)
        commands.publish(twist)
    client.create_subscription(Odometry, '/robot0/odom', answer, 100)
    spin_until(executor, lambda: len(poses) > STEPS, timeout=30.0, what='the lockstep run')
    world = load_world('', [('robot0', (1.0, 2.0, 0.3))], SimulationSettings())
    expected = [world.pose('robot0')]
    for step in range(STEPS + 1):
        world.command('robot0', *command_at(step))
        world.step()
        expected.append(world.pose('robot0'))
    assert world.pose('robot0') == simulator.simulation.pose('robot0')
    # The messages carry the heading as a quaternion: equal to its last bit or so.
    assert np.array([poses[stamp] for stamp in sorted(poses)]) == pytest.approx(
        np.array(expected[:STEPS + 1]), rel=0.0, abs=1e-12)
    assert world.stalled('robot0'), 'the run ends pushing against the wall'
    assert world.robot_poses().shape == (1, 3)
    assert set(world.sensor_readings('robot0')) == {'laser_0', *(f'sonar_{k}' for k in range(5))}


def test_a_policy_drives_the_live_robot_and_reports_as_the_lab_asks(ros_context, executor):
    """A policy on the observation alone, as it would run in the environment, through ROS."""
    def policy(observation):
        distance, bearing = observation[-5], math.atan2(observation[-3], observation[-4])
        turn = math.atan2(observation[-1], observation[-2])
        if distance > 0.05:
            return 0.5 * math.cos(bearing) * min(1.0, 2.0 * distance), 2.0 * bearing
        return 0.0, 2.0 * turn
    _, client = simulator_and_client(ros_context, executor, real_time_factor=5.0)
    statuses = []
    client.create_subscription(String, 'robot_status', lambda message: statuses.append(
        message.data), 100)
    controller = PolicyController(policy, [(2.0, 2.5, 1.0), (2.5, 2.0, -0.5)],
                                  context=ros_context)
    executor.add_node(controller)
    spin_until(executor, controller.finished.done, timeout=60.0, what='FINISHED')
    spin_until(executor, lambda: statuses and statuses[-1] == 'FINISHED', what='the statuses')
    assert [status.split()[0] for status in statuses] == ['STARTED', 'WAYPOINT', 'WAYPOINT',
                                                          'FINISHED']


def test_the_bridge_sees_what_the_environment_sees():
    arena = Arena(1, TaskSettings(), sensor_noise=False)
    arena.restart(0, np.random.default_rng(3))
    arena.courses.start(arena.poses)
    observation = arena.observations()
    laser = arena.laser
    scan = LaserScan(angle_min=laser.min_angle, range_max=laser.max_range,
                     angle_increment=(laser.max_angle - laser.min_angle) / (laser.num_rays - 1),
                     ranges=arena.ranges[0].tolist())
    ranges = scan_at(scan, np.linspace(laser.min_angle, laser.max_angle, laser.num_rays))
    assert np.array_equal(observe(ranges[None, :], laser.max_range, arena.poses,
                                  arena.courses.goals), observation)
    assert pytest.approx(ranges) == arena.ranges[0]


def test_the_python_pages_examples_run_as_shown(tmp_path, monkeypatch):
    """doc/python.md's blocks, in order and in one namespace, as a reader runs them."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv('SDL_VIDEODRIVER', 'dummy')
    page = Path(__file__).resolve().parents[2] / 'doc' / 'python.md'
    blocks = re.findall(r'```python\n(.*?)```', page.read_text(), re.DOTALL)
    assert len(blocks) == 6
    namespace = {}
    for block in blocks:
        exec(compile(block, str(page), 'exec'), namespace)
    assert namespace['observations'].shape == (100, 69)
    assert sorted(namespace['seen']) == ['robot0', 'robot1', 'robot2', 'robot3']
    assert not namespace['rclpy'].ok()
