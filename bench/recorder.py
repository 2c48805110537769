"""
Does record_run keep pace with a swarm? 1000 robots' odometry at 10 Hz into one bag.

Runs stdr_lite with the robots (odom_rate_hz 10) and record_run on '*/odom' as two processes
for a while, then reads the bag back and prints how many odometry messages it holds, at what
rate, and how many stamps are missing from any robot's sequence (0 means nothing dropped).

    python -m bench.recorder [--robots 1000] [--seconds 20]
"""

import argparse
from collections import Counter
from pathlib import Path
import signal
import subprocess
from tempfile import TemporaryDirectory
import time

from bench.realtime import keep_dds_on_loopback, write_robot_grid
from mcap.reader import make_reader
from rosbags.typesys import get_typestore, Stores
from simple_robot_control.share import installed_executable

ODOMETRY_PERIOD_NS = 100_000_000


def start(arguments, log):
    """Start one of the package's executables with its output in log."""
    return subprocess.Popen([installed_executable(arguments[0]), *arguments[1:]], stdout=log,
                            stderr=subprocess.STDOUT, text=True)


def wait_for(ready, what, timeout=120.0):
    deadline = time.monotonic() + timeout
    while not ready():
        if time.monotonic() > deadline:
            raise SystemExit(f'bench.recorder: no {what} within {timeout} s')
        time.sleep(0.1)


def missing_stamps(bag):
    """Count odometry messages per topic and the stamps missing between consecutive ones."""
    store = get_typestore(Stores.ROS2_JAZZY)
    last, counts, missing = {}, Counter(), 0
    with open(bag, 'rb') as stream:
        for _, channel, message in make_reader(stream).iter_messages():
            stamp = store.deserialize_cdr(message.data, 'nav_msgs/msg/Odometry').header.stamp
            now = stamp.sec * 10 ** 9 + stamp.nanosec
            if channel.topic in last:
                missing += (now - last[channel.topic]) // ODOMETRY_PERIOD_NS - 1
            last[channel.topic] = now
            counts[channel.topic] += 1
    return counts, missing


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--robots', type=int, default=1000)
    parser.add_argument('--seconds', type=float, default=20.0)
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    if args.smoke:
        args.robots, args.seconds = 5, 1.0
    keep_dds_on_loopback()
    with TemporaryDirectory() as folder:
        folder = Path(folder)
        robots = write_robot_grid(folder, args.robots)
        bag = folder / 'swarm.mcap'
        with open(folder / 'sim.log', 'w') as sim_log, open(folder / 'rec.log', 'w') as rec_log:
            simulator = start(['stdr_lite', '--ros-args', '-p', f'robots_file:={robots}', '-p',
                               'odom_rate_hz:=10.0'], sim_log)
            wait_for(lambda: 'real_time_factor' in (folder / 'sim.log').read_text(),
                     'start line from stdr_lite')
            recorder = start(['record_run', '--ros-args', '-p', f'bag:={bag}', '-p',
                              "topics:=['*/odom']"], rec_log)
            # Recording from its first odometry topic on, for the seconds measured.
            wait_for(lambda: bag.exists() and bag.stat().st_size > 0, 'bag from record_run')
            time.sleep(args.seconds)
            for process in (recorder, simulator):
                process.send_signal(signal.SIGINT)
                process.wait(timeout=60)
        counts, missing = missing_stamps(bag)
        with open(bag, 'rb') as stream:
            statistics = make_reader(stream).get_summary().statistics
        seconds = (statistics.message_end_time - statistics.message_start_time) * 1e-9
    total = sum(counts.values())
    sent = total + missing
    print(f'record_run, {args.robots} robots at 10 Hz: {len(counts)} odometry topics, '
          f'{total:,} messages in {seconds:.1f} s ({total / seconds:,.0f} per s), '
          f'{min(counts.values())}-{max(counts.values())} per robot, '
          f'{missing} stamps missing: {total / sent:.3f} of what was sent recorded')


if __name__ == '__main__':
    main()
