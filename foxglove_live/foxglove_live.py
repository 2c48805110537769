"""
foxglove_live: watch and drive any run from Foxglove, live over one WebSocket port.

The PyPI route to ROS 2 has no foxglove_bridge and no RViz; this serves the run's topics with
Foxglove's own server library (see live_view.py), on localhost unless asked, so that from
another machine `ssh -L 8765:localhost:8765 <host>` is all it takes. With bag set it records
the same topics too (see bag_recording.py): one process, file and socket.
"""

import ipaddress
import socket
import sys

from foxglove_live.live_view import BACKLOG, exposure_line, LiveView
from foxglove_live.parameters import PARAMETERS
from rclpy.task import Future
from simple_robot_control.bag_recording import BagRecording
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters


DESCRIPTION = ("foxglove_live: serve a run's topics (the map, robots, lasers, sonars, TF, "
               'robot_status; any topic) to Foxglove over its WebSocket protocol, live, and '
               "let Foxglove's Teleop panel drive a robot through its cmd_vel. Open Foxglove, "
               'connect to ws://localhost:8765. Stops on Ctrl-C.')


class FoxgloveLive(GuardedNode):
    """A node that serves the graph's topics to Foxglove (see LiveView), and may record them."""

    def __init__(self, port=None, backlog=BACKLOG, **kwargs):
        super().__init__('foxglove_live', **kwargs)
        # Serving ends only when asked to (Ctrl-C): nothing sets this.
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        host = params['host']
        self.live = LiveView(self, params['topics'], host,
                             params['port'] if port is None else port, params['command_topics'],
                             backlog)
        self.recording = (BagRecording(self, params['bag'], params['topics'], send_times=True)
                          if params['bag'] else None)
        print(connection_line(host, self.live.port), flush=True)
        warning = exposure_line(host, self.live.port)
        if warning:
            self.get_logger().warn(warning)

    def ending_allowance(self) -> float:
        """Return the seconds finishing the bag may take, for the end after Ctrl-C."""
        return 0.0 if self.recording is None else self.recording.finish_seconds()

    def shut_down(self) -> None:
        """Disconnect the clients; finish the bag, if any."""
        self.live.close()
        if self.recording is not None:
            self.recording.close()


def connection_line(host: str, port: int) -> str:
    """Return the line telling a user where to point Foxglove, from here or through ssh."""
    if is_wildcard(host):
        # 0.0.0.0 or :: is where a server listens (every address), never one to connect to.
        return (f'foxglove_live: open Foxglove and connect to ws://localhost:{port} (from '
                f'another machine: ws://{socket.gethostname()}:{port})')
    if exposure_line(host, port) is not None:
        return f'foxglove_live: open Foxglove and connect to ws://{url_host(host)}:{port}'
    return (f'foxglove_live: open Foxglove and connect to ws://localhost:{port} (from another '
            f'machine: ssh -L {port}:localhost:{port} <this machine>, then the same)')


def is_wildcard(host: str) -> bool:
    """Whether host is the unspecified address (0.0.0.0, ::): every interface of this machine."""
    try:
        return ipaddress.ip_address(host).is_unspecified
    except ValueError:
        return False


def url_host(host: str) -> str:
    """Return host as a URL writes it: an IPv6 address in brackets."""
    return f'[{host}]' if ':' in host else host


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('foxglove_live', DESCRIPTION, PARAMETERS)
    sys.exit(run('foxglove_live', parser, lambda options: FoxgloveLive(), argv))


if __name__ == '__main__':
    main()
