"""
A private channel to the process that supervises the simulation (grade_lab), beside ROS.

The supervisor starts stdr_lite with one end of a connected Unix socket inherited as
supervisor_fd. Over it, and nowhere else, the simulation plays (the supervisor writes `play`),
and every robot's true state of each published step goes out as one line:

    truth <name> <sim ns> <wall ns> <x> <y> <theta> <stalled 0|1>

after one header line, `limits <dt s> <linear m/s> <angular rad/s>`, the fastest any robot may
move. Nothing else can reach or forge it: the socket is no name in the file system, and the
process is made non-dumpable, so that another process of the same user can neither read its
file descriptors through /proc nor attach to it. When the supervisor's end closes, the
simulation ends. A supervised simulator serves nothing that moves, resets, steps, spawns or
deletes (stdr_lite.py leaves those services, the action and initialpose out).
"""

from __future__ import annotations

import ctypes
import socket
import time
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # at run time the node hands its simulation over; nothing more is loaded
    from stdr_lite.core.simulation import Simulation

_PR_SET_DUMPABLE = 4
PLAY = b'play\n'
POLL_PERIOD = 0.02


def forbid_inspection() -> None:
    """Make this process non-dumpable: no ptrace, no /proc/<pid>/fd for other processes."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_DUMPABLE, 0, 0, 0, 0)
    except (OSError, AttributeError):
        pass


class SupervisorLink:
    """The simulator's end of the supervisor's socket: plays on its word, writes the truth."""

    def __init__(self, node, descriptor: int, play, quit_now):
        forbid_inspection()
        try:
            self._socket = socket.socket(fileno=descriptor)
        except OSError as error:
            raise ValueError(f'supervisor_fd {descriptor}: not a socket ({error.strerror})') \
                from None
        self._socket.setblocking(False)
        self._play, self._quit = play, quit_now
        self._pending = b''
        self._open = True
        self._timer = node.create_timer(POLL_PERIOD, self._read)

    def send_limits(self, dt: float, linear: float, angular: float) -> None:
        """Say the step and the fastest motion the simulation allows."""
        self._send(f'limits {dt!r} {linear!r} {angular!r}\n')

    def send_truth(self, simulation: Simulation, sim_ns: int) -> None:
        """Send every robot's true pose and stall flag of the step just published."""
        wall_ns = time.time_ns()  # the clock DDS stamps its messages with
        lines = []
        for name in simulation.robot_names:
            x, y, theta = simulation.pose(name)
            lines.append(f'truth {name} {sim_ns} {wall_ns} {x!r} {y!r} {theta!r} '
                         f'{int(simulation.stalled(name))}\n')
        self._send(''.join(lines))

    def _send(self, text):
        if not self._open:
            return
        self._socket.setblocking(True)
        try:
            self._socket.sendall(text.encode())
        except OSError:
            self._closed()
        finally:
            if self._open:
                self._socket.setblocking(False)

    def _read(self):
        try:
            data = self._socket.recv(4096)
        except BlockingIOError:
            return
        except OSError:
            data = b''
        if not data:
            self._closed()
            return
        self._pending = (self._pending + data)[-4096:]
        while b'\n' in self._pending:
            line, self._pending = self._pending.split(b'\n', 1)
            if line + b'\n' == PLAY:
                self._play()

    def _closed(self):
        """End the simulation: its supervisor is gone, and it has no one to answer to."""
        if self._open:
            self._open = False
            self._quit()
