"""
Measure how fast stdr_lite and waypoint_controller run in lockstep (a benchmark, not a test).

The bundled lab tour is driven at rate_hz 50 with the simulator in lockstep and unpaced:
once with both nodes in this process on one EventsExecutor, once with the controller as a
separate process. The real-time factor is simulated seconds per wall second from the first
step to FINISHED; the control-step latency is the wall time from publishing odometry to
receiving the cmd_vel that answers it. Each configuration runs several times and the run with
the median RTF is shown. Last, the bare World steps N robots with wall and robot collision,
and the sensors of ten robots are read.
"""

import argparse
from contextlib import contextmanager
import os
from pathlib import Path
import random
import signal
import subprocess
import sys
from tempfile import TemporaryDirectory
import time

from nav_msgs.msg import Odometry
import numpy as np
import rclpy
from rclpy.context import Context
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import BUNDLED_COURSE, BUNDLED_MAP, BUNDLED_ROBOT, shared_file
from std_msgs.msg import String
from stdr_lite.core.robot_description import load_robot, RobotEntry
from stdr_lite.core.simulation import Simulation, SimulationSettings
from stdr_lite.core.world import PlacementError
from stdr_lite.node.stdr_lite import StdrLite
from waypoint_controller.waypoint_controller import WaypointController

RUN_TIMEOUT = 300.0


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
def ros_session():
    """Give (context, executor) of a Context of their own; destroy every node afterwards."""
    context = Context()
    rclpy.init(context=context)
    executor = EventsExecutor(context=context)
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
                    [os.path.join(os.path.dirname(sys.executable), 'waypoint_controller'),
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
    """Step robot_count robots with random commands in the lab room; robot-steps per second."""
    simulation, rng = crowded_simulation(robot_count, seed)
    for name in simulation.robot_names:
        simulation.command(name, rng.uniform(-0.5, 0.5), rng.uniform(-1.0, 1.0))
    started = time.perf_counter()
    for _ in range(steps):
        simulation.step()
    return robot_count * steps / (time.perf_counter() - started)


def node_real_time_factor(robot_count, listened, seconds=5.0):
    """
    Sim seconds per wall second of the whole stdr_lite node, free-running unpaced.

    The robots carry no sensors and stand still; every step publishes every robot's odometry
    (and /clock), listened to by a node in this process when listened is true.
    """
    with TemporaryDirectory() as folder, ros_session() as (context, executor):
        robots = write_robot_grid(Path(folder), robot_count)
        simulator = StdrLite(context=context, parameter_overrides=[
            Parameter('robots_file', value=str(robots)), Parameter('real_time_factor', value=0.0)])
        executor.add_node(simulator)
        if listened:
            listener = Node('listener', context=context)
            for name in simulator.simulation.robot_names:
                listener.create_subscription(Odometry, f'/{name}/odom', lambda _: None, 10)
            executor.add_node(listener)
        spin_until(executor, lambda: simulator.sim_time > 0.0)
        started_sim, started_wall = simulator.sim_time, time.perf_counter()
        deadline = started_wall + seconds
        while time.perf_counter() < deadline:
            executor.spin_once(timeout_sec=0.1)
        return (simulator.sim_time - started_sim) / (time.perf_counter() - started_wall)


def write_robot_grid(folder, robot_count):
    """Write a list of robot_count sensorless robots on a grid in the lab room."""
    (folder / 'plain.yaml').write_text('footprint: {radius: 0.2}\n')
    rows = [f'  - {{description: plain.yaml, pose: [{0.6 + 0.47 * (k % 40):.2f}, '
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


def main(argv=None):
    keep_dds_on_loopback()
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--course', default=shared_file(*BUNDLED_COURSE))
    parser.add_argument('--robots', type=int, nargs='+', default=[1, 100, 1000])
    parser.add_argument('--repeat', type=int, default=5,
                        help='runs per configuration; the run with the median RTF is shown')
    args = parser.parse_args(argv)
    print(f'course {args.course}, stdr_lite at rate_hz 50 in lockstep, real_time_factor 0')
    print(f'{"configuration":16} {"sim s":>7} {"wall s":>7} {"RTF":>7} {"RTF range":>13} '
          f'{"latency med":>12} {"latency p99":>12}')
    for label, separate in (('one process', False), ('two processes', True)):
        runs = sorted((drive_course(args.course, separate) for _ in range(args.repeat)),
                      key=lambda run: run[0] / run[1])
        sim, wall, latencies = runs[len(runs) // 2]
        slowest, fastest = (run[0] / run[1] for run in (runs[0], runs[-1]))
        median, p99 = np.percentile(latencies, (50, 99)) * 1e3
        print(f'{label:16} {sim:7.2f} {wall:7.2f} {sim / wall:6.1f}x '
              f'{slowest:5.1f}-{fastest:5.1f}x {median:9.2f} ms {p99:9.2f} ms', flush=True)
    print(f'{"robots":>7} {"robot-steps/s":>14} {"steps/s":>9}')
    for count in args.robots:
        rate = robot_steps_per_second(count, steps=max(200, 20000 // count))
        print(f'{count:7d} {rate:14,.0f} {rate / count:9,.0f}', flush=True)
    print('the whole stdr_lite node, free-running unpaced, odometry of every robot published')
    print(f'{"robots":>7} {"RTF":>9} {"RTF, odometry listened to":>26}')
    for count in args.robots:
        alone, listened = (node_real_time_factor(count, listened) for listened in (False, True))
        print(f'{count:7d} {alone:8.2f}x {listened:25.2f}x', flush=True)
    loads = sensor_load()
    print(f'sensors of 10 lab robots (667-ray laser, 5 sonars, 10 Hz each): '
          f'{np.median(loads):.1%} of one core (median of {len(loads)} batches, '
          f'{min(loads):.1%} to {max(loads):.1%})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
