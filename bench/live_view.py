"""
Is foxglove_live fair? A client that reads, alone and beside clients that never read.

Runs stdr_lite (real time) and foxglove_live as two processes. A reading client subscribes to
/clock and counts the share of its ticks it gets in a few seconds alone; then the idle clients
connect, subscribe to every channel (the map included) and read nothing, and the reading client
counts again; then they vanish. Prints the reading client's share beside them over its share
alone, and foxglove_live's memory (resident set) before, with and after the idle clients.

    python -m bench.live_view [--idle 200] [--seconds 5]
"""

import argparse
from pathlib import Path
import re
import signal
import subprocess
from tempfile import TemporaryDirectory
import time
from typing import NamedTuple

from bench.foxglove_client import FoxgloveClient
from bench.realtime import keep_dds_on_loopback
from bench.recorder import start, wait_for
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock

WATCHED = '/clock'


def resident_mb(process):
    """Return a process's resident set size in MB, from /proc."""
    status = Path(f'/proc/{process.pid}/status').read_text()
    return int(re.search(r'VmRSS:\s+(\d+) kB', status).group(1)) / 1024


def offered(client, topics):
    def ready():
        client.poll()
        return set(topics) <= set(client.channels)
    return ready


def stamp(time_message):
    return time_message.sec * 10 ** 9 + time_message.nanosec


def share_received(client, seconds):
    """
    Read for seconds; return the share of the /clock ticks published meanwhile that came.

    The clock ticks at a steady period, so the ticks between the first and last received are
    the ones published: a client whose oldest messages were dropped has gaps.
    """
    client.poll()
    first = len(client.messages[WATCHED])
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        client.poll()
        time.sleep(0.01)
    ticks = sorted({stamp(deserialize_message(payload, Clock).clock)
                    for _, payload in client.messages[WATCHED][first:]})
    if len(ticks) < 2:
        return 0.0
    period = min(later - earlier for earlier, later in zip(ticks, ticks[1:]))
    return len(ticks) / ((ticks[-1] - ticks[0]) // period + 1)


class Figures(NamedTuple):
    alone: float
    beside: float
    baseline_mb: float
    with_idle_mb: float
    after_mb: float


def measure(port: int, live: subprocess.Popen, idle_clients: int, seconds: float) -> Figures:
    """Measure a reading client's share alone and beside idle clients, and live's memory."""
    reader = FoxgloveClient(port)
    wait_for(offered(reader, ('/map', WATCHED)), 'the run offered')
    reader.subscribe(WATCHED)
    wait_for(lambda: reader.poll() or len(reader.messages[WATCHED]) > 0, 'a first /clock')
    baseline_mb = resident_mb(live)
    alone = share_received(reader, seconds)
    idle = []
    for _ in range(idle_clients):
        client = FoxgloveClient(port, receive_buffer=4096)
        wait_for(offered(client, ('/map', WATCHED)), 'the run offered to an idle client')
        client.subscribe(*client.channels)
        idle.append(client)
        reader.poll()
    beside = share_received(reader, seconds)
    with_idle_mb = resident_mb(live)
    for client in idle:
        client.vanish()
    deadline = time.monotonic() + 20.0
    while resident_mb(live) > baseline_mb * 1.1 and time.monotonic() < deadline:
        reader.poll()
        time.sleep(0.1)
    after_mb = resident_mb(live)
    reader.close()
    return Figures(alone, beside, baseline_mb, with_idle_mb, after_mb)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--idle', type=int, default=200, help='clients that never read')
    parser.add_argument('--seconds', type=float, default=5.0, help='each count lasts this')
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    if args.smoke:
        args.idle, args.seconds = 20, 2.0
    keep_dds_on_loopback()
    with TemporaryDirectory() as folder:
        folder = Path(folder)
        with open(folder / 'sim.log', 'w') as sim_log, open(folder / 'live.log', 'w') as log:
            simulator = start(['stdr_lite', '--ros-args', '-p', 'real_time_factor:=1.0'],
                              sim_log)
            live = start(['foxglove_live', '--ros-args', '-p', 'port:=0'], log)
            try:
                said = folder / 'live.log'
                wait_for(lambda: 'connect to ws://' in said.read_text(), "foxglove_live's line")
                port = int(re.search(r'ws://localhost:(\d+)', said.read_text()).group(1))
                figures = measure(port, live, args.idle, args.seconds)
            finally:
                for process in (live, simulator):
                    process.send_signal(signal.SIGINT)
                    process.wait(timeout=60)
    print(f'foxglove_live, a reading client on /clock: {figures.alone:.3f} of the ticks alone, '
          f'{figures.beside:.3f} beside {args.idle} idle clients: '
          f'{figures.beside / max(figures.alone, 1e-9):.2f} of its share')
    print(f'foxglove_live memory: {figures.baseline_mb:.0f} MB before, '
          f'{figures.with_idle_mb:.0f} MB with the idle clients, {figures.after_mb:.0f} MB '
          'after they left')


if __name__ == '__main__':
    main()
