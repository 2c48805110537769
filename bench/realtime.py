"""
Measure how fast stdr_lite and waypoint_controller run in lockstep (a benchmark, not a test).

The bundled lab tour is driven at rate_hz 50 with the simulator in lockstep and unpaced:
once with both nodes in this process on one EventsExecutor, once with the controller as a
separate process. Each run is paired with a run of the rclpy ceiling for the same loop
(bench.round_trip: Odometry out, Twist back, nothing else) in the same arrangement, and the
lab tour's real-time factor is printed as a ratio of that ceiling: ratios, measured side by
side, are what hold on a noisy machine. The real-time factor is simulated seconds per wall
second from the first step to FINISHED; the control-step latency is the wall time from
publishing odometry to receiving the cmd_vel that answers it. Before those, the bare Bodies
steps N robots with wall and robot contact; after, the whole node steps 1000 lab robots with
odometry at 10 Hz and a subscriber to every robot's odometry, timed by /clock against the wall
clock; last the sensors of ten robots are read. Every figure is the median of --repeat runs.
"""

import argparse
from contextlib import contextmanager
import os
from pathlib import Path
import random
import signal
import subprocess
import sys
from tempfile import mkdtemp, TemporaryDirectory
import time

from bench.round_trip import round_trip_rtf
import numpy as np
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import (BUNDLED_MAP, BUNDLED_ROBOT, installed_executable,
                                        shared_file)
from std_msgs.msg import String
from stdr_lite.core.bodies import PlacementError
from stdr_lite.core.robot_description import load_robot, RobotEntry
from stdr_lite.core.simulation import Simulation, SimulationSettings
from stdr_lite.node.stdr_lite import StdrLite
from waypoint_controller.waypoint_controller import WaypointController
from waypoint_lab.rules import BUNDLED_COURSE

RUN_TIMEOUT = 300.0
# The bare Bodies' target at 1000 robots (issue 41): times real time at 50 Hz.
CROWD_TARGET = 20.0


class StatusWatch(Node):
    """Notes the time robot_status says FINISHED or ABORTED."""

    def __init__(self, context):
        super().__init__('realtime_bench', context=context)
        self.last = None
        everything = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                                durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(String, 'robot_status', self._on_status, everything)

    def _on_status(self, message):
        if message.data.split()[0] in ('FINISHED', 'ABORTED'):
            self.last = message.data


def spin_until(executor, condition, timeout=RUN_TIMEOUT):
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise RuntimeError(f'no result within {timeout:g} s')
        executor.spin_once(timeout_sec=0.1)


@contextmanager
def ros_session(message_info=False):
    """
    Give (context, executor) of a Context of their own; destroy every node afterwards.

    The executor is rclpy's EventsExecutor, or with message_info its SingleThreadedExecutor,
    which hands subscriptions each message's info (its source timestamp) as well.
    """
    context = Context()
    rclpy.init(context=context)
    executor = (SingleThreadedExecutor(context=context) if message_info
                else EventsExecutor(context=context))
    try:
        yield context, executor
    finally:
        for node in executor.get_nodes():
            executor.remove_node(node)
            node.destroy_node()
        executor.shutdown()
        rclpy.try_shutdown(context=context)


def drive_course(course, separate_process):
    """Run the course; return (sim seconds, wall seconds, answer latencies in seconds)."""
    controller_process = None
    with ros_session() as (context, executor):
        try:
            simulator = StdrLite(context=context, parameter_overrides=[
                Parameter('lockstep', value=True), Parameter('real_time_factor', value=0.0)])
            watch = StatusWatch(context)
            for node in (simulator, watch):
                executor.add_node(node)
            if separate_process:
                controller_process = subprocess.Popen(
                    [installed_executable('waypoint_controller'),
                     course, '--ros-args', '--log-level', 'warn'])
            else:
                executor.add_node(WaypointController(course, context=context))
            spin_until(executor, lambda: simulator.sim_time > 0.0)
            started_sim, started_wall = simulator.sim_time, time.perf_counter()
            spin_until(executor, lambda: watch.last is not None)
            wall = time.perf_counter() - started_wall
            if watch.last != 'FINISHED':
                raise RuntimeError(f'the course ended with {watch.last}')
            latencies = np.array(simulator.stepper.answer_latencies)
            return simulator.sim_time - started_sim, wall, latencies
        finally:
            if controller_process is not None:
                if controller_process.poll() is None:
                    controller_process.send_signal(signal.SIGINT)
                controller_process.wait(timeout=30)


def demo_phases(course, real_time_factor):
    """
    Wall seconds of waypoint_controller's start, loop and end, arranged as `make demo` runs it.

    stdr_lite is a process of its own in lockstep at real_time_factor, and a robot_status
    reader (here, as course_monitor in the demo) is already there; once the simulator's
    odometry is in the graph, the controller starts as a process. Start is from its launch to
    the STARTED it logs, loop from STARTED to FINISHED, end from FINISHED to its exit.
    """
    simulator = subprocess.Popen([installed_executable('stdr_lite'), '--ros-args',
                                  '-p', 'lockstep:=true',
                                  '-p', f'real_time_factor:={real_time_factor!r}',
                                  '--log-level', 'warn'])
    try:
        with ros_session() as (context, executor):
            reader = StatusWatch(context)
            executor.add_node(reader)
            spin_until(executor, lambda: reader.count_publishers('/robot0/odom') > 0, 60.0)
            return controller_phases(course)
    finally:
        simulator.send_signal(signal.SIGINT)
        simulator.wait(timeout=60)


def controller_phases(course):
    """Run waypoint_controller on course; return its (start, loop, end) in wall seconds."""
    marks = {'launch': time.perf_counter()}
    controller = subprocess.Popen([installed_executable('waypoint_controller'), course],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for line in controller.stdout:
        for word in ('STARTED', 'FINISHED'):
            if word in line:
                marks.setdefault(word, time.perf_counter())
    controller.wait(timeout=RUN_TIMEOUT)
    marks['exit'] = time.perf_counter()
    if 'FINISHED' not in marks or 'STARTED' not in marks:
        raise RuntimeError(f'the controller did not finish the course (exit code '
                           f'{controller.returncode})')
    return (marks['STARTED'] - marks['launch'], marks['FINISHED'] - marks['STARTED'],
            marks['exit'] - marks['FINISHED'])


def print_demo_phases(course, repeat, real_time_factor=4.0):
    phases = np.median([demo_phases(course, real_time_factor) for _ in range(repeat)], axis=0)
    start, loop, end = phases
    print(f"the demo's run (stdr_lite and waypoint_controller as processes, lockstep at "
          f'{real_time_factor:g}x), median of {repeat}: start {start:.2f} s ({start / loop:.3f} '
          f'of the loop), loop {loop:.2f} s, end {end:.2f} s ({end / loop:.3f} of the loop); '
          f'wall time {start + end:.2f} s over the loop', flush=True)


def crowded_simulation(robot_count, seed):
    """Return the lab room with robot_count lab robots at random free poses."""
    simulation = Simulation(load_map(shared_file(*BUNDLED_MAP)), SimulationSettings(rate_hz=50.0))
    description = load_robot(shared_file(*BUNDLED_ROBOT))
    rng = np.random.default_rng(seed)
    while len(simulation.robot_names) < robot_count:
        x, y = rng.uniform((0.0, 0.0), simulation.occupancy_map.extent)
        entry = RobotEntry(f'robot{len(simulation.robot_names)}', description,
                           (x, y, rng.uniform(-np.pi, np.pi)))
        try:
            simulation.add_robot(entry)
        except PlacementError:
            continue
    return simulation, rng


def robot_steps_per_second(robot_count, steps, seed=1):
    """
    Step robot_count robots with random commands in the lab room; robot-steps per CPU-second.

    CPU time, not wall time: on a shared machine the wall clock moves with the load.
    """
    simulation, rng = crowded_simulation(robot_count, seed)
    for name in simulation.robot_names:
        simulation.command(name, rng.uniform(-0.5, 0.5), rng.uniform(-1.0, 1.0))
    started = time.process_time()
    for _ in range(steps):
        simulation.step()
    return robot_count * steps / (time.process_time() - started)


class ClockWatch(Node):
    """Notes the wall time each /clock message arrives, with the sim time it carries."""

    def __init__(self, context):
        super().__init__('clock_watch', context=context)
        self.ticks = []
        self.create_subscription(Clock, '/clock', self._on_clock, 10)

    def _on_clock(self, message):
        self.ticks.append((time.perf_counter(),
                           message.clock.sec + message.clock.nanosec * 1e-9))


def node_real_time_factor(robot_count, seconds, odom_rate_hz=10.0):
    """
    Sim seconds per wall second of the whole stdr_lite node, free-running unpaced.

    robot_count lab robots (laser and sonars, unread) stand on a grid; every robot's odometry
    goes out at odom_rate_hz to a subscriber in a process of its own (bench.odometry_listener,
    as RViz or the robots' controllers would be), and /clock, heard over seconds of wall time
    once the subscriber has every topic, gives the pace. Above 1, the node holds real time.
    """
    listener = subprocess.Popen([sys.executable, '-m', 'bench.odometry_listener',
                                 str(robot_count)])
    try:
        with TemporaryDirectory() as folder, ros_session() as (context, executor):
            robots = write_robot_grid(Path(folder), robot_count)
            simulator = StdrLite(context=context, parameter_overrides=[
                Parameter('robots_file', value=str(robots)),
                Parameter('real_time_factor', value=0.0),
                Parameter('odom_rate_hz', value=odom_rate_hz)])
            watch = ClockWatch(context)
            for node in (simulator, watch):
                executor.add_node(node)
            spin_until(executor, lambda: simulator.odometry_subscribers() >= robot_count)
            first = len(watch.ticks)
            deadline = time.perf_counter() + seconds
            while time.perf_counter() < deadline:
                executor.spin_once(timeout_sec=0.1)
            (wall_start, sim_start), (wall_end, sim_end) = watch.ticks[first], watch.ticks[-1]
            return (sim_end - sim_start) / (wall_end - wall_start)
    finally:
        listener.send_signal(signal.SIGINT)
        listener.wait(timeout=60)


def write_robot_grid(folder, robot_count):
    """Write a list of robot_count lab robots on a grid in the lab room."""
    description = shared_file(*BUNDLED_ROBOT)
    rows = [f'  - {{description: {description}, pose: [{0.6 + 0.47 * (k % 40):.2f}, '
            f'{0.6 + 0.55 * (k // 40):.2f}, 0.0]}}' for k in range(robot_count)]
    path = folder / 'robots.yaml'
    path.write_text('robots:\n' + '\n'.join(rows) + '\n')
    return path


def keep_dds_on_loopback():
    """Confine DDS to loopback in a domain of this run's own, for us and the controller."""
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    os.environ['ROS_STATIC_PEERS'] = ''
    os.environ.setdefault('ROS_DOMAIN_ID', str(random.SystemRandom().randint(1, 100)))


def sensor_load(robot_count=10, batches=5, repeats=20, seed=2):
    """
    Fraction of one core that robot_count lab robots' lasers and sonars take at 10 Hz.

    Returns one figure per batch of repeated reads, so that the spread shows.
    """
    simulation, _ = crowded_simulation(robot_count, seed)
    jobs = [(name, sensor.spec) for name in simulation.robot_names
            for sensor in simulation.robot(name).sensors]
    frequency = min(spec.frequency for _, spec in jobs)
    loads = []
    for _ in range(batches):
        started = time.perf_counter()
        for _ in range(repeats):
            simulation.read_sensors(jobs)
        loads.append((time.perf_counter() - started) / repeats * frequency)
    return loads


def lockstep_against_ceiling(course, separate_process, repeat, ceiling_seconds):
    """Run the lab tour and the ceiling in turn; return the runs and each run's ratio."""
    tours, ceilings = [], []
    for _ in range(repeat):
        with ros_session() as (context, executor):
            ceilings.append(round_trip_rtf(context, executor, separate_process,
                                           seconds=ceiling_seconds))
        tours.append(drive_course(course, separate_process))
    ratios = [sim / wall / ceiling for (sim, wall, _), ceiling in zip(tours, ceilings)]
    return tours, ceilings, ratios


def print_lockstep(course, repeat, ceiling_seconds):
    print(f'course {course}, stdr_lite at rate_hz 50 in lockstep, real_time_factor 0; '
          f'median of {repeat} runs, each beside a run of the rclpy ceiling (bench.round_trip)')
    print(f'{"configuration":14} {"RTF":>7} {"ceiling":>8} {"ratio":>6} {"ratio range":>12} '
          f'{"latency med":>12} {"latency p99":>12}')
    for label, separate in (('one process', False), ('two processes', True)):
        tours, ceilings, ratios = lockstep_against_ceiling(course, separate, repeat,
                                                           ceiling_seconds)
        middle = sorted(range(repeat), key=lambda run: tours[run][0] / tours[run][1])[repeat // 2]
        sim, wall, latencies = tours[middle]
        median, p99 = np.percentile(latencies, (50, 99)) * 1e3
        print(f'{label:14} {sim / wall:6.1f}x {np.median(ceilings):7.1f}x '
              f'{np.median(ratios):6.2f} {min(ratios):5.2f}-{max(ratios):5.2f} '
              f'{median:9.2f} ms {p99:9.2f} ms', flush=True)


def main(argv=None):
    keep_dds_on_loopback()
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--course', default=shared_file(*BUNDLED_COURSE))
    parser.add_argument('--robots', type=int, nargs='+', default=[1, 100, 1000])
    parser.add_argument('--crowd', type=int, default=1000,
                        help='lab robots in the whole-node run')
    parser.add_argument('--node-seconds', type=float, default=20.0,
                        help='wall seconds of /clock per whole-node run')
    parser.add_argument('--repeat', type=int, default=5,
                        help='runs per figure; the median is shown')
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    ceiling_seconds = 3.0
    if args.smoke:
        args.robots, args.crowd, args.node_seconds, args.repeat = [1, 10], 10, 1.0, 1
        ceiling_seconds = 0.5
        args.course = os.path.join(mkdtemp(), 'one_waypoint.txt')
        Path(args.course).write_text('2 2 0\n')
    # The bare Bodies first, in a process that has run nothing else yet: measured after the
    # lockstep runs, it came out a third slower.
    print('the bare Bodies (the step of the core without sensors or ROS), walls and robot contact '
          f'included, in CPU time; median of {args.repeat} runs')
    print(f'{"robots":>7} {"robot-steps/s":>14} {"steps/s":>9} {"real time at 50 Hz":>19}')
    for count in args.robots:
        rate = float(np.median([robot_steps_per_second(count, steps=max(200, 20000 // count))
                                for _ in range(args.repeat)]))
        factor = rate / count / 50
        verdict = 'met' if factor >= CROWD_TARGET else 'missed'
        target = f'  (target >= {CROWD_TARGET:g}x: {verdict})' if count == 1000 else ''
        print(f'{count:7d} {rate:14,.0f} {rate / count:9,.0f} {factor:18,.1f}x{target}',
              flush=True)
    print_lockstep(args.course, args.repeat, ceiling_seconds)
    print_demo_phases(args.course, args.repeat)
    factors = [node_real_time_factor(args.crowd, args.node_seconds) for _ in range(args.repeat)]
    print(f'the whole stdr_lite node, {args.crowd} lab robots, free-running unpaced, odometry '
          f'at 10 Hz to a subscriber: {np.median(factors):.2f}x real time by /clock over '
          f'{args.node_seconds:g} s (median of {args.repeat}, {min(factors):.2f} to '
          f'{max(factors):.2f}x)', flush=True)
    loads = sensor_load()
    print(f'sensors of 10 lab robots (667-ray laser, 5 sonars, 10 Hz each): '
          f'{np.median(loads):.1%} of one core (median of {len(loads)} batches, '
          f'{min(loads):.1%} to {max(loads):.1%})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
