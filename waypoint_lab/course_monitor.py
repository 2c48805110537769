"""
course_monitor: print robot_status as it arrives, show progress, and record the run.

It only listens, so it can watch any controller's run of the lab, including one already under
way: robot_status is transient local, so it still receives every message from STARTED on. A
status is dated as run.py dates it, by the latest odometry heard before it (one heard before
any odometry, by the first). The record is a rosbag2 bag in MCAP (bag_recording.py), which
plot_run draws.
"""

import math
import os
import sys
import time

from nav_msgs.msg import Odometry
from rclpy.clock import Clock, ClockType
from rclpy.serialization import deserialize_message
from rclpy.task import Future
from rclpy.time import Time
from simple_robot_control.bag_recording import BagRecording
from simple_robot_control.exit_codes import EXIT_FAILED, EXIT_OK
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import pose_from_message
from simple_robot_control.validation import shorten
from std_msgs.msg import String
from waypoint_lab.interface import load_course, status_qos
from waypoint_lab.parameters import COURSE_MONITOR_PARAMETERS, RUN_TOPICS
from waypoint_lab.rules import STATUS_TOPIC
from waypoint_lab.status import (ABORTED, FINISHED, parse_status, STARTED, UNREACHABLE,
                                 WAYPOINT)

PROGRESS_PERIOD = 0.1
BAR_WIDTH = 20


DESCRIPTION = ('course_monitor: print each robot_status message of a waypoint_controller run '
               'as it arrives, with a progress line (waypoints done, sim and wall time) on a '
               'terminal, and optionally record the run for plot_run. Exits 0 on FINISHED, '
               '1 on ABORTED. Give it the same course and tolerances as the controller.')


class CourseMonitor(GuardedNode):
    """Listens to robot_status and odometry; the output goes to write(text)."""

    def __init__(self, waypoint_file=None, write=None, interactive=None, **kwargs):
        super().__init__('course_monitor', **kwargs)
        self.finished = Future()
        params = declare_parameters(self, COURSE_MONITOR_PARAMETERS)
        path, waypoints = load_course(self, waypoint_file, params['waypoint_file'])
        self._write = write or _write_stdout
        self._interactive = sys.stdout.isatty() if interactive is None else interactive
        self._total = len(waypoints)
        self._done = 0
        # The latest odometry stamp heard (seconds); None before any.
        self.sim_time = None
        # The odometry stamp of STARTED, once there is odometry to date it by.
        self._sim_started = None
        self._started_unseen = False
        self._wall_started = None
        self._progress_shown = False
        topics = RUN_TOPICS + ((params['map_topic'],) if params['map_topic'] else ())
        self.recording = (BagRecording(self, params['bag'], topics, inputs=[path],
                                       send_times=True, course=os.path.basename(path))
                          if params['bag'] else None)
        if self.recording is not None:
            # From the start, as the monitor hears them: a status is dated by what came before.
            # The recording hands each status on once it is in the bag, so that the run's last
            # status, which ends the monitor, is in the bag too.
            self.recording.record_now(
                f'/{STATUS_TOPIC}', 'std_msgs/msg/String', status_qos(self._total),
                then=lambda data, sent: self._on_status(deserialize_message(data, String)),
                keep=lambda data: self._course_status(deserialize_message(data, String).data)
                is not None)
        else:
            self.create_subscription(String, STATUS_TOPIC, self._on_status,
                                     status_qos(self._total))
        self.create_subscription(Odometry, f'{params["robot_name"]}/odom', self._on_odometry,
                                 100)
        self.create_timer(PROGRESS_PERIOD, self._show_progress,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))

    def _on_odometry(self, message):
        stamp = Time.from_msg(message.header.stamp).nanoseconds * 1e-9
        pose = pose_from_message(message.pose.pose)
        if not all(map(math.isfinite, pose)):
            self.get_logger().warn('ignoring odometry whose pose is not finite',
                                   throttle_duration_sec=5.0)
            return
        self.sim_time = stamp
        if self._started_unseen:
            self._sim_started, self._started_unseen = stamp, False

    def _on_status(self, message):
        if self.finished.done():
            return
        text = message.data
        status = self._course_status(text)
        if status is None:
            # Some other node spoke on robot_status: say so (the record keeps it out).
            self._clear_progress()
            self._write(f'(not a status of this course: {shorten(repr(text), 80)})\n')
            return
        kind = status.kind
        date = self.sim_time
        if kind == STARTED:
            self._wall_started = time.monotonic()
            self._sim_started, self._started_unseen = date, date is None
        elif kind in (WAYPOINT, UNREACHABLE):
            # A goal given up (the planning coursework) is behind the robot as one reached.
            self._done += 1
        self._clear_progress()
        self._write(text + '\n')
        if kind in (FINISHED, ABORTED):
            self._write(self._progress_text(date) + '\n')
            self.finished.set_result(EXIT_OK if kind == FINISHED else EXIT_FAILED)
        else:
            self._show_progress()

    def _course_status(self, text):
        """Return text as a status of this course, or None (another node's words)."""
        status = parse_status(text)
        if status is None or (status.number is not None and not status.number <= self._total):
            return None
        return status

    def _progress_text(self, sim_time=None):
        sim_time = self.sim_time if sim_time is None else sim_time
        run_time = (0.0 if sim_time is None or self._sim_started is None
                    else sim_time - self._sim_started)
        wall = 0.0 if self._wall_started is None else time.monotonic() - self._wall_started
        filled = round(BAR_WIDTH * self._done / self._total)
        return (f'[{"#" * filled}{"." * (BAR_WIDTH - filled)}] {self._done}/{self._total} '
                f'waypoints | sim {run_time:.1f} s | '
                f'wall {wall:.1f} s')

    def _show_progress(self):
        """Redraw the progress line in place; only on a terminal, where it can be redrawn."""
        if self._interactive and not self.finished.done():
            self._write('\r' + self._progress_text() + '\x1b[K')
            self._progress_shown = True

    def _clear_progress(self):
        if self._progress_shown:
            self._write('\r\x1b[K')
            self._progress_shown = False

    def ending_allowance(self) -> float:
        """Return the seconds finishing the bag may take, for the end after Ctrl-C."""
        return 0.0 if self.recording is None else self.recording.finish_seconds()

    def shut_down(self) -> None:
        """Finish the bag, so that even an interrupted run leaves a complete one."""
        self._clear_progress()
        if self.recording is not None:
            self.recording.close()


def _write_stdout(text):
    sys.stdout.write(text)
    sys.stdout.flush()


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('course_monitor', DESCRIPTION, COURSE_MONITOR_PARAMETERS)
    parser.add_argument('waypoint_file', nargs='?', metavar='WAYPOINT_FILE',
                        help='the course the controller follows (for the waypoint count and '
                        'the record); the waypoint_file parameter is the alternative')
    sys.exit(run('course_monitor', parser,
                 lambda options: CourseMonitor(options.waypoint_file), argv))


if __name__ == '__main__':
    main()
