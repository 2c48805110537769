"""
Measure how long requests hold the simulation back (a benchmark, not a test).

stdr_lite runs as a process of its own at rate_hz 50 and real time, so /clock comes every
20 ms. This process listens to /clock and sends bursts of the largest requests the simulator
accepts: spawns of 16 KB robot descriptions, entity filters with 1000-point convex hulls, a
folder of 200 spawnable files of 16 KB, and a world of 4096 x 4096 cells. The robots carry as
many sensors as a robot may (32 sonars), each a topic of its own. For each burst it prints the
longest and the 99th percentile gap between two /clock messages while the burst was served (and
the same for a while with no requests, to compare), and how long the burst took: medians of
--repeat runs. Gaps are between the times the simulator sent its /clock messages (their source
timestamps), so that this process's own work on the requests (serialising 100,000 points
takes it a fifth of a second) is not taken for the simulator's. A new world stands STOPPED
with its clock back at 0: the gaps of a world loading are those of the old world's steps while
the new one loads. The target: no gap beyond 100 ms, five step periods.
"""

import argparse
import math
from pathlib import Path
import signal
import subprocess
from tempfile import TemporaryDirectory
import time

from bench.realtime import keep_dds_on_loopback, ros_session, spin_until
from geometry_msgs.msg import PoseStamped
import numpy as np
from PIL import Image
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.time import Time
from rosgraph_msgs.msg import Clock
from simple_robot_control.input_files import MAX_DESCRIPTION_BYTES
from simple_robot_control.pose import set_pose
from simple_robot_control.share import installed_executable
from simulation_interfaces.msg import Bounds, EntityFilters
from simulation_interfaces.srv import GetEntities, GetSpawnables, LoadWorld, SpawnEntity
from stdr_lite.core.robot_description import MAX_SENSORS

PERIOD = 0.02
# The longest a request may hold /clock back: five step periods.
TARGET = 0.1
# The side of the world loaded, in cells, and a smoke run's.
WORLD_CELLS, SMOKE_WORLD_CELLS = 4096, 256
SERVICE_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
SONAR = ('    - {{frame_id: sonar_{}, cone_angle: 0.5, min_range: 0.1, max_range: 3, '
         'frequency: 10}}\n')


def largest_description():
    """Return a robot with as many sonars as it may carry, padded to the largest size accepted."""
    text = 'footprint: {radius: 0.2}\nsensors:\n  sonars:\n' + ''.join(
        SONAR.format(index) for index in range(MAX_SENSORS))
    padding = '# ' + 'x' * 76 + '\n'
    return text + padding * ((MAX_DESCRIPTION_BYTES - len(text)) // len(padding))


def pose(x, y):
    message = PoseStamped()
    set_pose(message.pose, float(x), float(y), 0.0)
    return message


class Client(Node):
    """Listens to /clock and calls the simulator's services."""

    def __init__(self, context):
        super().__init__('request_bench', context=context)
        self.arrivals = []
        self.create_subscription(Clock, '/clock', self._on_clock, 1000)  # with its MessageInfo
        self._callers = {}

    def call_all(self, executor, kind, service, requests):
        """Send every request at once; wait for every answer; return the seconds it took."""
        if service not in self._callers:
            client = self.create_client(kind, f'/stdr_lite/{service}', qos_profile=SERVICE_QOS)
            spin_until(executor, client.service_is_ready, timeout=30.0)
            self._callers[service] = client
        started = time.monotonic()
        futures = [self._callers[service].call_async(request) for request in requests]
        spin_until(executor, lambda: all(future.done() for future in futures))
        return time.monotonic() - started

    def _on_clock(self, message, info):
        """Note when the simulator sent the clock (wall seconds) and the time it carries."""
        self.arrivals.append((info['source_timestamp'] * 1e-9,
                              Time.from_msg(message.clock).nanoseconds))

    def gaps(self, since, until):
        """
        Return the gaps between /clock messages around since to until, one step either side.

        From the last one before since to the first one after until, so that a burst shorter
        than a step still shows the gap around it.

        A new world restarts the clock at 0 and stands STOPPED: what comes after is not the
        simulation held back, and is left out.
        """
        times, last = [], -1
        moments = [moment for moment, _ in self.arrivals]
        before = max((moment for moment in moments if moment < since), default=since)
        after = min((moment for moment in moments if moment > until), default=until)
        for moment, stamp in self.arrivals:
            if before <= moment <= after:
                if stamp < last:
                    break
                times.append(moment)
                last = stamp
        return np.diff(times) if len(times) > 1 else np.array([math.nan])


def bursts(folder, size=1.0, cells=WORLD_CELLS):
    """
    Return (label, service type, service name, requests) of every burst, in order.

    size scales the bursts' counts (a smoke run takes a hundredth).
    """
    spawns, filters, points, files = (max(1, round(count * size))
                                      for count in (50, 50, 100_000, 200))
    description = largest_description()
    for index in range(files):
        (folder / 'spawnables' / f'robot{index:03d}.yaml').write_text(description)
    hull = Bounds(type=Bounds.TYPE_CONVEX_HULL, points=[
        pose(10 + 5 * math.cos(k / 160), 7 + 5 * math.sin(k / 160)).pose.position
        for k in range(1000)])
    return [
        (f'{spawns} spawns of 32 sonars', SpawnEntity, 'spawn_entity', [SpawnEntity.Request(
            name=f'bot{k}', resource_string=description, initial_pose=pose(
                3 + k % 15, 4 + 0.5 * (k // 15))) for k in range(spawns)]),
        (f'{filters} hull filters', GetEntities, 'get_entities', [GetEntities.Request(
            filters=EntityFilters(filter='^bot', bounds=hull)) for _ in range(filters)]),
        (f'a {points:,}-point hull', GetEntities, 'get_entities', [GetEntities.Request(
            filters=EntityFilters(bounds=Bounds(type=Bounds.TYPE_CONVEX_HULL, points=[
                pose(k % 300, k // 300).pose.position for k in range(points)])))]),
        (f'{files} files of spawnables', GetSpawnables, 'get_spawnables', [
            GetSpawnables.Request(sources=[str(folder / 'spawnables')])]),
        (f'a {cells}x{cells} world', LoadWorld,
         'load_world', [LoadWorld.Request(uri=str(folder / 'big.yaml'))]),
    ]


def write_big_world(folder, cells=WORLD_CELLS):
    pixels = np.full((cells, cells), 254, dtype=np.uint8)
    pixels[::64, :] = pixels[:, ::64] = 0
    pixels[:200, :200] = 254
    Image.fromarray(pixels).save(folder / 'big.pgm')
    (folder / 'big.yaml').write_text('image: big.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n')


def measure_once(folder, size=1.0, quiet=2.0, cells=WORLD_CELLS):
    """Run the simulator and every burst once; return {label: (longest, p99, seconds)}."""
    simulator = subprocess.Popen(
        [installed_executable('stdr_lite'), '--ros-args',
         '--log-level', 'warn'])
    figures = {}
    try:
        with ros_session(message_info=True) as (context, executor):
            client = Client(context)
            executor.add_node(client)
            spin_until(executor, lambda: len(client.arrivals) > 50, timeout=60.0)
            quiet_from = time.time()
            spin_until(executor, lambda: time.time() > quiet_from + quiet)
            gaps = client.gaps(quiet_from, time.time())
            figures['no requests'] = (gaps.max(), np.percentile(gaps, 99), quiet)
            for label, kind, service, requests in bursts(folder, size, cells):
                started = time.time()
                seconds = client.call_all(executor, kind, service, requests)
                ended = time.time()
                # The next /clock, unless a new world stands stopped (none comes then).
                deadline = time.monotonic() + 5 * PERIOD
                while client.arrivals[-1][0] <= ended and time.monotonic() < deadline:
                    executor.spin_once(timeout_sec=PERIOD)
                gaps = client.gaps(started, ended)
                figures[label] = (gaps.max(), np.percentile(gaps, 99), seconds)
    finally:
        simulator.send_signal(signal.SIGINT)
        simulator.wait(timeout=30)
    return figures


def main(argv=None):
    parser = argparse.ArgumentParser(prog='bench.requests', description=__doc__.split('\n')[1])
    parser.add_argument('--repeat', type=int, default=3)
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    if args.smoke:
        args.repeat = 1
    keep_dds_on_loopback()
    with TemporaryDirectory() as directory:
        folder = Path(directory)
        (folder / 'spawnables').mkdir()
        size, cells = (0.01, SMOKE_WORLD_CELLS) if args.smoke else (1.0, WORLD_CELLS)
        write_big_world(folder, cells)
        runs = [measure_once(folder, size, 0.5 if args.smoke else 2.0, cells)
                for _ in range(args.repeat)]
    print(f'gaps between /clock messages of stdr_lite at 50 Hz (a step is {PERIOD * 1e3:.0f} ms) '
          f'while a burst of requests is served; medians of {args.repeat} runs')
    print(f'{"burst":26} {"longest gap":>12} {"p99 gap":>9} {"served in":>10}  '
          f'target ({TARGET * 1e3:.0f} ms)')
    for label in runs[0]:
        longest, p99, seconds = (np.median([run[label][part] for run in runs])
                                 for part in range(3))
        if math.isnan(longest):
            # Served before the next /clock, in a new world that stands stopped: no gap to see.
            print(f'{label:26} {"-":>9} ms {"-":>6} ms {seconds:8.2f} s  met (within a step)')
            continue
        verdict = 'met' if longest <= TARGET else f'{longest / TARGET:.2f}x over'
        print(f'{label:26} {longest * 1e3:9.1f} ms {p99 * 1e3:6.1f} ms {seconds:8.2f} s  '
              f'{verdict}')


if __name__ == '__main__':
    main()
