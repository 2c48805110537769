"""The stdr_lite node: the simulation core on STDR's topics and the standard simulation API."""

import argparse
import array
from collections.abc import Iterator
import math
import sys

from nav_msgs.msg import MapMetaData, OccupancyGrid
from nav_msgs.srv import GetMap
import numpy as np
from rcl_interfaces.msg import SetParametersResult
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock as ClockMsg
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import compose, planar_pose
from simple_robot_control.validation import ConfigError, describe, shorten
from simulation_interfaces.msg import SimulationState
from stdr_lite.core.bodies import PlacementError
from stdr_lite.core.commands import CommandOutcome
from stdr_lite.core.entities import RequestError
from stdr_lite.core.robot_description import RobotDescription
from stdr_lite.node.control_services import SimulationControl
from stdr_lite.node.entity_services import EntityServices
from stdr_lite.node.frames import FramePublisher
from stdr_lite.node.graph_watch import GraphWatch
from stdr_lite.node.health import HealthWatch
from stdr_lite.node.messages import map_message, set_stamp
from stdr_lite.node.naming import check_robot_names, NamingProblem
from stdr_lite.node.parameters import (frames, ON_DEMAND_ABOVE, PARAMETERS, search_path,
                                       STDR_STATIC_FRAME)
from stdr_lite.node.process_settings import settle_for_large_requests
from stdr_lite.node.requests import RequestQueue
from stdr_lite.node.robot_topics import RobotTopics
from stdr_lite.node.served import Served
from stdr_lite.node.simulation_setup import build_simulation, start_line
from stdr_lite.node.stepper import Stepper
from stdr_lite.node.supervisor_link import SupervisorLink

DESCRIPTION = ('stdr_lite: a small STDR-equivalent simulator. For each robot, subscribes '
               '/<robot>/cmd_vel (geometry_msgs/Twist) and /<robot>/initialpose; publishes '
               '/<robot>/odom (nav_msgs/Odometry), /<robot>/ground_truth, /<robot>/stall '
               '(std_msgs/Bool), /<robot>/laser_J (sensor_msgs/LaserScan), /<robot>/sonar_J '
               '(sensor_msgs/Range), /tf and /tf_static. Also /map (transient '
               'local, and as nav_msgs/GetMap on map_server/map and static_map) and /clock; the '
               'standard simulation_interfaces services and the SimulateSteps action under '
               '/stdr_lite/ control time, entities and worlds.')
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
# nav_msgs/GetMap under the names code waits for: nav2_map_server's, and ROS 1's map_server's.
MAP_SERVICES = ('map_server/map', 'static_map')


class StdrLite(GuardedNode):
    """
    Unicycle robots and obstacles in a map_server world, stepped at a fixed rate.

    The Stepper decides when a step happens (paced, lockstep, played or paused); the node
    publishes what each step makes due, and keeps every robot's topics, the TF frames and the
    markers in line with the entities, whatever adds or removes them.
    """

    def __init__(self, **kwargs):
        super().__init__('stdr_lite', **kwargs)
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        self.frames = frames(params)
        self.search_path = search_path(params)
        self.simulation, self.default_description = build_simulation(params, self.search_path)
        for name in self.simulation.robot_names:
            robot = self.simulation.robot(name)
            try:
                check_robot_names(self, self.frames, robot.namespace, robot.description)
            except NamingProblem as problem:
                raise ConfigError(f'robot {shorten(name)}: {problem}') from None
        self._noted = set()
        self._supervisor = self._supervision(params)
        for name in self.simulation.robot_names:
            self.note_description(name, self.simulation.robot(name).description)
        self.requests = RequestQueue(self)
        self._stamped = params['cmd_vel_stamped']
        self._optional_topics = params['optional_topics']
        self._frame_publisher = FramePublisher(self, self.frames, self.simulation)
        self._topics = {}
        self._clock_publisher = self.create_publisher(ClockMsg, '/clock', 10)
        self._clock_message = ClockMsg()
        # A mapping coursework hides the world's map: its geometry alone goes out.
        self._map_visible = params['map_visible']
        self._map_publisher = (self.create_publisher(OccupancyGrid, '/map', LATCHED)
                               if self._map_visible else
                               self.create_publisher(MapMetaData, '/map_metadata', LATCHED))
        self.stepper = Stepper(self, self.simulation, self._step, self._publish_state,
                               self.odometry_subscribers, params['real_time_factor'],
                               params['lockstep'])
        self.sync_entities()
        self._map = map_message(self.simulation.occupancy_map, self.frames.map_frame)
        self._publish_map()
        self._serve(params)
        self._begin(params)
        self.get_logger().info(start_line(self.simulation, params, self._supervisor is not None))

    def _supervision(self, params):
        """Return the link to a supervisor (grade_lab) if one started the node, else None."""
        if params['supervisor_fd'] < 0:
            return None
        try:
            link = SupervisorLink(self, int(params['supervisor_fd']),
                                  lambda: self.stepper.set_state(SimulationState.STATE_PLAYING),
                                  self.quit_soon)
        except ValueError as error:
            raise ConfigError(str(error)) from None
        # Its pace and its world are the grader's: use_sim_time set by a submission would
        # freeze its timers on a clock nobody publishes.
        self.add_on_set_parameters_callback(lambda _: SetParametersResult(
            successful=False, reason='a supervised simulator takes no parameter changes'))
        return link

    def _serve(self, params):
        """Serve the map, the simulation API and the watches (fewer under a supervisor)."""
        for name in MAP_SERVICES:
            self.requests.serve(GetMap, name, self._answer_map, private=False)
        # In lockstep the controller sets the pace by design: only free-running can lag.
        HealthWatch(self, self.simulation, self._topics,
                    0.0 if params['lockstep'] else params['real_time_factor'],
                    lambda: self.stepper.playing)
        GraphWatch(self, self._topics)
        served = Served(self.simulation, self.stepper, self.frames, self.search_path,
                        self.entity_topics, self.restart, self.show_state, self.note_description,
                        self.quit_soon)
        world_changing = self._supervisor is None
        self._control = SimulationControl(self, served, world_changing)
        EntityServices(self, served, world_changing)

    def _begin(self, params):
        """Tell a supervisor the limits, and start paused (supervised) or in lockstep."""
        if self._supervisor is not None:
            settings = self.simulation.settings
            self._supervisor.send_limits(
                self.simulation.dt,
                settings.max_linear_speed or settings.safety_linear_speed,
                settings.max_angular_speed or settings.safety_angular_speed)
        if params['paused'] or self._supervisor is not None:
            self.stepper.set_state(SimulationState.STATE_PAUSED)
        if params['lockstep']:
            self.simulation.odometry_due()
            self.stepper.start_over(new_time=True)

    @property
    def sim_time(self) -> float:
        """Return the simulated seconds since start."""
        return self.simulation.sim_time

    def sync_entities(self) -> None:
        """Give every robot its topics and no other, all at once (at start, or in a test)."""
        for _ in self.entity_topics():
            pass

    def entity_topics(self) -> Iterator[None]:
        """
        Give every robot its topics and no other, yielding between endpoints (a generator).

        A robot that went loses its topics, and a new one gets its own, before the first
        yield, so that every robot of the simulation has its odometry and commands between
        any two steps; then the endpoints are withdrawn and the sensors' made one at a time.
        Frames and markers are published anew soon.
        """
        gone = [self._topics.pop(name) for name in set(self._topics)
                - set(self.simulation.robot_names)]
        on_demand = (self._optional_topics == 'on_demand' or self._optional_topics == 'auto'
                     and len(self.simulation.robot_names) > ON_DEMAND_ABOVE)
        for name in self.simulation.robot_names:
            if name not in self._topics:
                self._topics[name] = RobotTopics(self, self.simulation.robot(name), self.frames,
                                                 self._stamped, self._on_cmd_vel,
                                                 self._on_initial_pose if self._supervisor is None
                                                 else None, self._on_truth_reader,
                                                 on_demand)
        self._frame_publisher.entities_changed()
        for topics in gone:
            yield from topics.dismantle()
        for topics in list(self._topics.values()):
            while not topics.complete:
                topics.make_sensor_topic()
                yield

    def restart(self, new_time: bool, grid: OccupancyGrid | None = None) -> Iterator[None]:
        """
        After a reset or a new world: publish the map (grid, if new), entities and state.

        new_time says whether the clock went back to 0. A generator, for the request's job.
        """
        self.stepper.release(everyone=new_time)
        if grid is not None:
            self._map = grid
            self._publish_map()
        yield from self.entity_topics()
        self._publish_clock()
        self.stepper.start_over(new_time)

    def _publish_map(self):
        """Publish the world's map on /map, or only its geometry where the map is hidden."""
        self._map_publisher.publish(self._map if self._map_visible else self._map.info)

    def _answer_map(self, request, response):
        """
        Answer GetMap with the current world, as /map has it (after any load_world).

        Where the map is hidden, with its geometry and every cell unknown: a mapper written the
        STDR way sizes its grid from static_map at start, and learns nothing more from it.
        """
        if self._map_visible:
            response.map = self._map
            return
        response.map.header, response.map.info = self._map.header, self._map.info
        response.map.data = array.array('b', bytes([0xFF]) * len(self._map.data))

    def show_state(self) -> None:
        """Publish the current state again (same stamp), as after a teleport while paused."""
        self._publish_state()
        self._frame_publisher.obstacles_moved()

    def note_description(self, name: str, description: RobotDescription) -> None:
        """Log, once per robot file, what it has unsimulated and whether its noise applies."""
        if description in self._noted:
            return
        self._noted.add(description)
        if description.unsimulated:
            self.get_logger().warn(f'robot {shorten(name)}: not simulated (stdr_lite has no such '
                                   f'sensors; kept by name): {", ".join(description.unsimulated)}')
        note = self.simulation.settings.sensor_noise_note(description)
        if note:
            self.get_logger().info(f'robot {shorten(name)}: {note}')

    def quit_soon(self) -> None:
        """End the node once the answer that asked for it has gone out."""
        def quit_now():
            self.destroy_timer(timer)
            if not self.finished.done():
                self.finished.set_result(0)
        timer = self.create_timer(0.2, quit_now)

    def _on_initial_pose(self, name, message):
        """
        Move a robot where initialpose or STDR's replace (stdr_msgs/MoveRobot) puts it.

        STDR's replace names a planar pose in the map frame (STDR's map_static under
        frame_style stdr); either is refused, and said in the log, into a wall or off the map.
        """
        what = 'initialpose' if hasattr(message, 'pose') else 'replace'
        try:
            if what == 'replace':
                pose = message.new_pose
                target = tuple(float(value) for value in (pose.x, pose.y, pose.theta))
                if not all(map(math.isfinite, target)):
                    raise ValueError(f'the pose {target} is not finite')
            else:
                target = planar_pose(message.pose.pose)
        except ValueError as error:
            self.get_logger().warn(f'{name}: {what} refused: {error}')
            return
        where = ', '.join(f'{value:g}' for value in target)
        frame = (message.header.frame_id if what == 'initialpose'
                 else STDR_STATIC_FRAME if self.frames.stdr else '')
        if self.frames.stdr and frame == STDR_STATIC_FRAME:
            target = compose(self.simulation.occupancy_map.origin, target)
        elif frame not in ('', self.frames.map_frame):
            also = f' or {STDR_STATIC_FRAME}' if self.frames.stdr else ''
            self.get_logger().warn(f'{name}: move to ({where}) refused: poses are in the '
                                   f'{self.frames.map_frame} frame{also}, not '
                                   f'{describe(frame)}')
            return
        try:
            self.simulation.teleport(name, target)
        except (PlacementError, RequestError) as error:
            self.get_logger().warn(f'{name}: move to ({where}) refused: {error}')
            return
        self.show_state()
        self.get_logger().info(f'{name} moved to ({where})')

    def _on_truth_reader(self, name):
        if name in self._topics:
            self._topics[name].publish_ground_truth(self.simulation.time_ns,
                                                    self.simulation.ground_truth(name))

    def _on_cmd_vel(self, name, twist):
        if name not in self.simulation:
            return
        linear, lateral, angular = twist.linear.x, twist.linear.y, twist.angular.z
        outcome = self.simulation.command(name, linear, angular, lateral)
        if outcome is not CommandOutcome.APPLIED:
            sideways = f', {lateral:g} m/s sideways' if lateral else ''
            why = outcome.value
            if outcome is CommandOutcome.SAFETY_BOUND:
                linear_bound, angular_bound = self.simulation.settings.safety
                why += (f' ({linear_bound:g} m/s, {angular_bound:g} rad/s; the parameters '
                        'safety_linear_speed and safety_angular_speed raise it)')
            self.get_logger().warn(f'{name}: command ({linear:g} m/s{sideways}, {angular:g} '
                                   f'rad/s) {why}', throttle_duration_sec=5.0)
        self.stepper.answered(name)

    def _step(self):
        """Advance one step and publish what falls due; return whether odometry went out."""
        self.simulation.step()
        self._publish_clock()
        published = self.simulation.odometry_due()
        if published:
            self._publish_state()
            if self.simulation.obstacles_moving:
                self._frame_publisher.obstacles_moved()
        self._publish_sensors()
        return published

    def _publish_clock(self):
        if self._clock_publisher.get_subscription_count():
            set_stamp(self._clock_message.clock, self.simulation.time_ns)
            self._clock_publisher.publish(self._clock_message)

    def _publish_state(self):
        """Publish every robot's odometry, ground truth and stall flag, and the moving frames."""
        simulation = self.simulation
        now_ns = simulation.time_ns
        for name, topics in self._topics.items():
            topics.publish_odometry(now_ns,
                                    self._frame_publisher.odometry_reading(simulation, name))
            if topics.ground_truth_listened:
                topics.publish_ground_truth(now_ns, simulation.ground_truth(name))
            if topics.stall_listened:
                topics.publish_stall(simulation.stalled(name))
        self._frame_publisher.publish_moving(simulation, now_ns)
        if self._supervisor is not None:
            self._supervisor.send_truth(simulation, now_ns)

    def _publish_sensors(self):
        """Read and publish the sensors that are due and that someone listens to."""
        jobs = [(name, spec) for name, spec in self.simulation.due_sensors(self._sensors_listened)
                if self._topics[name].listened(spec)]
        if not jobs:
            return
        now_ns = self.simulation.time_ns
        for (name, spec), reading in zip(jobs, self.simulation.read_sensors(jobs)):
            self._topics[name].publish_reading(spec, now_ns, reading)

    def _sensors_listened(self, name):
        return self._topics[name].any_listened()

    def odometry_subscribers(self) -> int:
        """Count the subscriptions to every robot's odometry."""
        return sum(topics.odom_publisher.get_subscription_count()
                   for topics in self._topics.values())

    def destroy_node(self) -> None:
        self._control.destroy()
        self.requests.close()
        super().destroy_node()

    def shut_down(self) -> None:
        """Answer the requests still queued, and log how long controllers took to answer."""
        self.requests.abandon('the simulator is shutting down')
        latencies = self.stepper.answer_latencies
        if self.stepper.lockstep and latencies:
            median, p99 = np.percentile(latencies, (50, 99)) * 1e3
            self.get_logger().info(
                f'lockstep: {self.simulation.step_count} steps, cmd_vel answered odometry '
                f'after {median:.2f} ms (median), {p99:.2f} ms (99th percentile)')


def built_simulator(options: argparse.Namespace) -> StdrLite:
    """Build the node, then set the process up for it (process_settings.py says why)."""
    node = StdrLite()
    settle_for_large_requests()
    return node


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('stdr_lite', DESCRIPTION, PARAMETERS)
    sys.exit(run('stdr_lite', parser, built_simulator, argv))


if __name__ == '__main__':
    main()
