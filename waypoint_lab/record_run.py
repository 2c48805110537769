"""
record_run: record a run's topics, or any, into a rosbag2 bag in MCAP until Ctrl-C.

The PyPI route to ROS 2 has no `ros2 bag`; this writes what Jazzy's `ros2 bag record -s mcap`
writes (see bag.py and bag_recording.py), for ros2 bag, Foxglove, rosbags and plot_run.
"""

import sys

from rclpy.task import Future
from simple_robot_control.bag_recording import BagRecording
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters
from waypoint_lab.parameters import RECORD_RUN_PARAMETERS


DESCRIPTION = ('record_run: record the topics of a run (robot_status, the course, odometry, '
               'ground truth, lasers, sonars, TF, map, clock; or those given) into a rosbag2 '
               'bag in MCAP that ros2 bag, Foxglove and plot_run read. Stops on Ctrl-C, '
               'leaving the bag complete.')


class RunRecorder(GuardedNode):
    """A node that only records (see BagRecording), with each message's send time."""

    def __init__(self, bag=None, topics=None, **kwargs):
        super().__init__('record_run', **kwargs)
        # Recording ends only when asked to (Ctrl-C): nothing sets this.
        self.finished = Future()
        params = declare_parameters(self, RECORD_RUN_PARAMETERS)
        self.recording = BagRecording(self, bag or params['bag'], topics or params['topics'],
                                      send_times=True)

    def ending_allowance(self) -> float:
        """Return the seconds finishing the bag may take, for the end after Ctrl-C."""
        return self.recording.finish_seconds()

    def shut_down(self) -> None:
        """Finish the bag, so that an interrupted recording is complete and indexed."""
        self.recording.close()


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('record_run', DESCRIPTION, RECORD_RUN_PARAMETERS)
    sys.exit(run('record_run', parser, lambda options: RunRecorder(), argv))


if __name__ == '__main__':
    main()
