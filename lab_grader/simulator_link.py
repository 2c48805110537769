"""
The grader's end of the simulator's private channel (stdr_lite's supervisor_fd). No ROS here.

The simulator's true state reaches the grader here, not over ROS: a socket that only the
grader and the simulator hold, so nothing the submission publishes can stand in for it. A
thread reads it as fast as it comes (the simulator waits when it is not read) and keeps the
graded robot's path; play() lets the simulation run.
"""

from dataclasses import dataclass
import math
import socket
import threading

# A line of the channel is short; one longer than this is no line of the simulator's.
MAX_LINE = 512


@dataclass(frozen=True)
class SpeedLimits:
    """The step and the fastest motion the simulator allows: a truer path is drivable."""

    dt: float
    linear: float
    angular: float


class SimulatorLink:
    """Holds the grader's end of the socket; truth() is the robot's path so far."""

    def __init__(self, robot_name: str):
        self._robot = robot_name
        self._ours, self.theirs = socket.socketpair()
        self.limits: SpeedLimits | None = None
        self.problem = ''
        self._path = []
        self._lock = threading.Lock()
        self._reader = threading.Thread(target=self._read, name='simulator link', daemon=True)

    @property
    def descriptor(self) -> int:
        """Return the simulator's end, for it to inherit (closed here by handed_over)."""
        return self.theirs.fileno()

    def handed_over(self) -> None:
        """Close the simulator's end here once it has inherited it, and start reading."""
        self.theirs.close()
        self._reader.start()

    def play(self) -> bool:
        """Ask the simulation to play; False if the simulator is gone."""
        try:
            self._ours.sendall(b'play\n')
            return True
        except OSError:
            return False

    def truth(self) -> list[tuple]:
        """Return the path so far: (sim s, (x, y, theta), wall ns sent, stalled) per step."""
        with self._lock:
            return list(self._path)

    @property
    def last_sent(self) -> int:
        """Return the wall time (ns) at which the latest true pose was sent, 0 before any."""
        with self._lock:
            return self._path[-1][2] if self._path else 0

    def close(self) -> None:
        """Close the channel (the simulator then ends), and wait for what it had sent."""
        try:
            self._ours.shutdown(socket.SHUT_WR)
        except OSError:
            pass
        if self._reader.is_alive():
            self._reader.join(timeout=10.0)
        self._ours.close()

    def _read(self):
        with self._ours.makefile('rb') as stream:
            for line in stream:
                try:
                    taken = len(line) <= MAX_LINE and self._take(
                        line.decode(errors='replace').split())
                except ValueError:
                    taken = False
                if not taken:
                    self.problem = f'the simulator sent {line[:80]!r} on its channel'
                    return

    def _take(self, words):
        if words[:1] == ['limits'] and len(words) == 4:
            values = [float(word) for word in words[1:]]
            if not all(math.isfinite(value) and value > 0 for value in values):
                return False
            self.limits = SpeedLimits(*values)
            return True
        if words[:1] != ['truth'] or len(words) != 8:
            return False
        if words[1] != self._robot:
            return True
        sim_ns, wall_ns = int(words[2]), int(words[3])
        pose = tuple(float(word) for word in words[4:7])
        with self._lock:
            self._path.append((sim_ns * 1e-9, pose, wall_ns, words[7] == '1'))
        return True
