"""
The rclpy ceiling of the lockstep loop: Odometry out, Twist back, and nothing else.

A pacer publishes nav_msgs/Odometry, its stamp one step later each time, and waits for the
geometry_msgs/Twist that answers it; an echo answers every odometry with a Twist. On one
EventsExecutor in one process, or with the echo in a process of its own (`python -m
bench.round_trip` runs one), it makes the most round trips per second that rclpy allows a
simulator and a controller in lockstep on this machine: the yardstick of bench.realtime.
"""

import argparse
import os
import signal
import subprocess
import sys
import time

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.task import Future
from simple_robot_control.node_runtime import run

ODOMETRY_TOPIC = '/robot0/odom'
COMMAND_TOPIC = '/robot0/cmd_vel'
QUEUE = 10
# An odometry unanswered this long (wall seconds) was sent before the echo was matched: again.
RESEND_AFTER = 0.2
NANOSECONDS = 1_000_000_000


class Pacer(Node):
    """Publishes the next odometry as soon as the last one is answered, and counts answers."""

    def __init__(self, step_ns, **kwargs):
        super().__init__('round_trip_pacer', **kwargs)
        self.round_trips = 0
        self._step_ns = step_ns
        self._time_ns = 0
        self._odometry = Odometry()
        self._odometry.header.frame_id = 'robot0/odom'
        self._odometry.child_frame_id = 'robot0/base_link'
        self._publisher = self.create_publisher(Odometry, ODOMETRY_TOPIC, QUEUE)
        self.create_subscription(Twist, COMMAND_TOPIC, self._on_command, QUEUE)
        self._sent_at = time.monotonic()

    def send(self):
        stamp = self._odometry.header.stamp
        stamp.sec, stamp.nanosec = divmod(self._time_ns, NANOSECONDS)
        self._publisher.publish(self._odometry)
        self._sent_at = time.monotonic()

    def resend_if_unanswered(self):
        if time.monotonic() - self._sent_at > RESEND_AFTER:
            self.send()

    def _on_command(self, _):
        self.round_trips += 1
        self._time_ns += self._step_ns
        self.send()


class HelperNode(Node):
    """A node of a bench helper process, run as the package's executables are, until a signal."""

    def __init__(self, name, **kwargs):
        super().__init__(name, **kwargs)
        self.finished = Future()

    def shut_down(self):
        """Leave with nothing more to say."""


class Echo(HelperNode):
    """Answers every odometry with a Twist, as a controller does, doing nothing else."""

    def __init__(self, **kwargs):
        super().__init__('round_trip_echo', **kwargs)
        self._command = Twist()
        self._publisher = self.create_publisher(Twist, COMMAND_TOPIC, QUEUE)
        self.create_subscription(Odometry, ODOMETRY_TOPIC, self._on_odometry, QUEUE)

    def _on_odometry(self, _):
        self._publisher.publish(self._command)


def round_trip_rtf(context, executor, separate_process, step_s=0.02, seconds=3.0,
                   echo_command=(sys.executable, '-m', 'bench.round_trip')):
    """
    Return the real-time factor of the bare loop at this step: sim seconds per wall second.

    The pacer and, unless separate_process, the echo are added to executor (in context); the
    caller destroys them. Counting starts with the first answer, so discovery is left out.
    """
    echo = None
    pacer = Pacer(round(step_s * NANOSECONDS), context=context)
    executor.add_node(pacer)
    if separate_process:
        echo = subprocess.Popen(list(echo_command))
    else:
        executor.add_node(Echo(context=context))
    try:
        deadline = time.monotonic() + 30.0
        pacer.send()
        while pacer.round_trips == 0:
            if time.monotonic() > deadline:
                raise RuntimeError('the echo never answered')
            executor.spin_once(timeout_sec=0.05)
            pacer.resend_if_unanswered()
        started_trips, started = pacer.round_trips, time.perf_counter()
        end = started + seconds
        while time.perf_counter() < end:
            executor.spin_once(timeout_sec=0.1)
        trips = pacer.round_trips - started_trips
        return trips * step_s / (time.perf_counter() - started)
    finally:
        if echo is not None:
            echo.send_signal(signal.SIGINT)
            try:
                echo.wait(timeout=10)
            except subprocess.TimeoutExpired:
                echo.kill()
                echo.wait()


def serve(parser, make_node, argv=None):
    """Run a helper node (make_node(options)) until SIGINT or SIGTERM; return an exit code."""
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        print(f'{parser.prog}: run through bench.realtime, which keeps DDS on loopback',
              file=sys.stderr)
        return 2
    return run(parser.prog, parser, make_node, argv)


def main(argv=None):
    """Run an echo until interrupted."""
    parser = argparse.ArgumentParser(
        prog='round_trip', description='the echo of the ceiling: a helper process that '
        'bench.realtime starts, not a benchmark (run python -m bench.realtime [--smoke])')
    return serve(parser, lambda _: Echo(), argv)


if __name__ == '__main__':
    sys.exit(main())
