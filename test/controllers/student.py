"""
A lab submission written for grade_lab's tests: it reports on robot_status as told, never drives.

    python3 student.py BEHAVIOUR WAYPOINT_FILE    (BEHAVIOUR @: the one the file ./behaviour names)

honest reports the pose it is at for every waypoint (right on a course whose waypoints are
the start pose); careful does too, once its publisher has matched a reader; early reports
each waypoint's own pose, reached or not; off10 reports its pose 10 cm off in x; silent never
reports; crash fails at once; hang reports STARTED and then sleeps forever; ignore_sigint and
fork report honestly, then the one ignores Ctrl-C and the other leaves a child behind in a
session of its own. Its robot_status publisher is rclpy's
default (reliable, volatile), as a student's is.
"""

import math
import os
import signal
import sys
import threading
import time

from nav_msgs.msg import Odometry
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def pose_of(odometry):
    orientation = odometry.pose.pose.orientation
    theta = math.atan2(2.0 * (orientation.w * orientation.z + orientation.x * orientation.y),
                       1.0 - 2.0 * (orientation.y ** 2 + orientation.z ** 2))
    return odometry.pose.pose.position.x, odometry.pose.pose.position.y, theta


def read_waypoints(path):
    with open(path) as stream:
        numbers = [float(word) for line in stream for word in line.split('#')[0].split()]
    return [(x, y, math.radians(theta))
            for x, y, theta in zip(numbers[0::3], numbers[1::3], numbers[2::3])]


def spin_for(node, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)


def main(behaviour, waypoint_file):
    if behaviour == 'crash':
        raise RuntimeError('this submission crashes on purpose')
    rclpy.init()
    node = Node('student')
    status = node.create_publisher(String, 'robot_status', 10)
    poses = []
    node.create_subscription(Odometry, 'robot0/odom', lambda message: poses.append(
        pose_of(message)), 10)
    if behaviour == 'careful':
        # Honest, and sure to be heard: DDS matching is asymmetric, so a reader that has
        # matched this publisher may not yet be matched by it.
        while not status.get_subscription_count():
            rclpy.spin_once(node, timeout_sec=0.1)
    print(f'student {behaviour}: waiting for odometry', flush=True)
    while not poses:
        rclpy.spin_once(node, timeout_sec=0.1)
    if behaviour == 'silent':
        while True:
            rclpy.spin_once(node, timeout_sec=0.1)

    def say(text, x, y, theta):
        status.publish(String(data=f'{text} {x:.3f} {y:.3f} {math.degrees(theta):.2f}'))
    x, y, theta = poses[-1]
    say('STARTED', x, y, theta)
    if behaviour == 'hang':
        threading.Event().wait()
    for number, waypoint in enumerate(read_waypoints(waypoint_file), start=1):
        spin_for(node, 0.2)
        reported = {'early': waypoint, 'off10': (x + 0.1, y, theta)}.get(behaviour, (x, y, theta))
        say(f'WAYPOINT {number}', *reported)
    status.publish(String(data='FINISHED'))
    if behaviour == 'ignore_sigint':
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        while True:
            rclpy.spin_once(node, timeout_sec=0.1)
    if behaviour == 'fork':
        if os.fork() == 0:
            os.setsid()
            signal.pause()
            os._exit(0)
        # Ends by itself well within the grader's 2 s after FINISHED, however loaded the
        # machine (an interpreter's teardown of rclpy can take a second), leaving its child.
        spin_for(node, 0.3)
        os._exit(0)
    spin_for(node, 1.0)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == '__main__':
    behaviour = sys.argv[1]
    if behaviour == '@':
        with open('behaviour') as named:
            behaviour = named.read().strip()
    main(behaviour, sys.argv[2])
