"""
The simulation: robots and obstacles by name in one world, stepped at a fixed rate. No ROS here.

Every change is made here: entities added and removed (a row of the one store of every
entity's state, state.py), commands, steps, resets and a new map. Every request is checked
whole before anything changes: a refusal raises and leaves the simulation as it was. What can
be read of it without a change (poses, velocities, odometry, sensors) is its base class's, in
readings.py. The stdr_lite node only turns messages into calls of this class and its results
into messages; tests, benchmarks and learning loops drive it directly.
"""

from dataclasses import replace
import math
from typing import Iterable
import zlib

import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.validation import compact, is_ros_name, ros_name_problem, shorten
from stdr_lite.core.bodies import Bodies, PlacementError
from stdr_lite.core.commands import CommandOutcome, HeldCommands
from stdr_lite.core.entities import (Category, NamespaceError, NANOSECONDS,
                                     PeriodicSchedule, RequestError, sensors_of, SimulatedEntity,
                                     SimulationSettings)
from stdr_lite.core.motion import motion_for, noisy_command
from stdr_lite.core.odometry import Odometry
from stdr_lite.core.readings import SimulationReadings
from stdr_lite.core.robot_description import RobotEntry
from stdr_lite.core.sensing import Sensing
from stdr_lite.core.state import StateTable
from stdr_lite.core.terrain import survey, Terrain

# Footprints up to this radius can be added while running, besides those in the start list.
LARGEST_ADDED_RADIUS = 0.5
# Up to this many robots, command_robots commands each as command() does: for so few, that
# costs less than gathering the rows (both apply the same limits, commands.py).
FEW_ROBOTS = 8


class Simulation(SimulationReadings):
    """
    Robots (unicycles or omni robots, round or polygonal) and obstacles, stepped every dt.

    Everything stands in one map and advances together every dt = 1/rate_hz.

    Each robot holds its last valid command until the next (as STDR does), or stops once the
    command is older than cmd_vel_timeout when that is positive; a moving obstacle keeps the
    velocity it was given.
    """

    def __init__(self, occupancy_map: OccupancyMap,
                 settings: SimulationSettings = SimulationSettings(),
                 robots: Iterable[RobotEntry] = ()):
        robots = list(robots)
        self.settings = settings
        self.dt_ns = round(NANOSECONDS / settings.rate_hz)
        self._odometry_period_ns = (self.dt_ns if settings.odom_rate_hz <= 0.0
                                    else round(NANOSECONDS / settings.odom_rate_hz))
        self.sensing = Sensing(settings.bodies_meet, settings.sensor_seed)
        self._kinds = (None, None)
        self._largest = max([LARGEST_ADDED_RADIUS] + [entry.description.radius
                                                      for entry in robots])
        self._rebuild(self.survey(occupancy_map), [])
        self._restart_time()
        for entry in robots:
            try:
                self.add_robot(entry)
            except (PlacementError, RequestError) as error:
                raise type(error)(f'{entry.name} in {occupancy_map.source}: {error}') from None

    def survey(self, occupancy_map: OccupancyMap) -> Terrain:
        """
        Derive what this simulation needs of a map, for load_map: the costly part of a switch.

        It reads nothing that changes while the simulation runs, so it may run in a thread of
        its own while the simulation steps on.
        """
        return survey(occupancy_map, self._largest)

    def _use(self, bodies):
        """Run on bodies (its terrain's, its state's entities): commands and odometry anew."""
        self.bodies, self.state = bodies, bodies.state
        self.commands = HeldCommands(self.state, self.settings.max_linear_speed,
                                     self.settings.max_angular_speed,
                                     self.settings.cmd_vel_timeout, self.settings.safety)
        self.odometer = Odometry(self.state, self.settings.odometry_noise,
                                 self.settings.odom_seed)
        self.sensing.attach(self.state, self.terrain.finder)

    def _restart_time(self):
        self.step_count = 0
        self.odometer.reseed(self.settings.odom_seed)
        for entity in self.state.entities:
            entity.motion_noise = self._motion_noise(entity.name, entity.description)
        self.odometry_schedule = PeriodicSchedule(self._odometry_period_ns, 0)
        self.sensing.restart(self.settings.sensor_seed, 0)

    def add_robot(self, entry: RobotEntry, spawned: bool = False, namespace: str = '') -> None:
        """
        Place a robot with its description at its pose; its topics go under namespace.

        Raises RequestError for a bad or taken name or namespace, or sensors faster than the
        steps, and PlacementError for a pose off the map, in a wall or on another entity;
        either way nothing changes.
        """
        self._check_new_name(entry.name)
        namespace = namespace.strip('/') or entry.name
        if not all(is_ros_name(token) for token in namespace.split('/')):
            raise NamespaceError(f'namespace {shorten(repr(namespace))} is not a ROS namespace')
        taken = [entity.name for entity in self.state.entities if entity.namespace == namespace]
        if taken:
            raise NamespaceError(f'namespace {namespace} is taken by {taken[0]}')
        for spec in entry.description.lasers + entry.description.sonars:
            if spec.frequency > self.settings.rate_hz:
                raise RequestError(f'sensor {spec.frame_id} reads at {compact(spec.frequency)} '
                                   f'Hz, faster than the simulation steps (rate_hz '
                                   f'{compact(self.settings.rate_hz)})')
        self._append(SimulatedEntity(entry.name, Category.ROBOT, entry.description.radius,
                                     entry.pose, spawned, entry.description, namespace,
                                     sensors_of(entry.description, self.time_ns,
                                                self.settings.applies_sensor_noise(
                                                    entry.description)),
                                     self._motion_noise(entry.name, entry.description)))

    def _motion_noise(self, name, description):
        """
        Return the generator of a robot's motion noise, if its kinematics has any.

        Each robot has its own, seeded from motion_seed and its name, so its noise does not
        depend on the order in which the robots' commands arrive.
        """
        if description is None or not description.kinematic.noisy:
            return None
        return np.random.default_rng([self.settings.motion_seed, zlib.crc32(name.encode())])

    def add_obstacle(self, name: str, radius: float, pose: tuple, moving: bool = False,
                     spawned: bool = True) -> None:
        """Place a circular obstacle, one that stays put or one that can be set moving."""
        self._check_new_name(name)
        if not 0.0 < radius <= self._largest:
            raise RequestError(f'an obstacle radius must be in (0, {compact(self._largest)}] m, '
                               f'got {compact(radius)}')
        category = Category.MOVING_OBSTACLE if moving else Category.STATIC_OBSTACLE
        self._append(SimulatedEntity(name, category, float(radius), tuple(pose), spawned))

    def _check_new_name(self, name):
        problem = ros_name_problem(name, 'a name')
        if problem is not None:
            raise RequestError(problem)
        if name in self.state:
            raise RequestError(f'an entity named {shorten(name)} exists already')

    def _append(self, entity):
        self.bodies.add_body(entity.start_pose, entity.radius, entity.shape, entity)

    def remove(self, name: str) -> None:
        """Take an entity out; the entities after it move down one row."""
        self.bodies.remove_body(self.state.index(name))

    def teleport(self, name: str, pose: tuple[float, float, float]) -> None:
        """
        Move an entity to pose, or raise PlacementError and leave it where it is.

        Drifting odometry does not notice (the robot was carried): map -> odom takes the jump.
        """
        self.bodies.move_body(self.state.index(name), pose)

    def command(self, name: str, linear: float, angular: float,
                lateral: float = 0.0) -> CommandOutcome:
        """
        Hold (linear m/s, angular rad/s, lateral m/s) for the robot from now on.

        The command meets the speed limits, then the robot's motion noise if it has any (drawn
        once per command, as STDR does); lateral (linear.y) moves an omni robot only.
        """
        robot = self.robot(name)
        index = self.state.index(name)
        if not all(map(math.isfinite, (linear, angular, lateral))):
            return CommandOutcome.IGNORED
        command, outcome = self.commands.limited(linear, lateral, angular)
        if robot.motion_noise is not None:
            command = noisy_command(command, robot.description.kinematic.parameters,
                                    robot.motion_noise)
        if robot.description.kinematic.model != 'omni':
            if lateral != 0.0 and outcome is CommandOutcome.APPLIED:
                outcome = CommandOutcome.NOT_OMNI
            command = (command[0], 0.0, command[2])
        self.commands.update(index, command, self.sim_time)
        return outcome

    def command_robots(self, linear: np.ndarray, angular: np.ndarray,
                       lateral: np.ndarray | None = None) -> None:
        """
        Hold a command for every robot at once, in robot_names order (a learning loop's).

        Each command is what command() would make of it: its limits, its robot's motion noise,
        a unicycle's lateral speed dropped; a command that is not finite is ignored.
        """
        rows = self.state.robot_rows
        lateral = np.zeros(len(rows)) if lateral is None else lateral
        if len(rows) <= FEW_ROBOTS:
            for row, values in zip(rows.tolist(), zip(linear.tolist(), angular.tolist(),
                                                      lateral.tolist())):
                self.command(self.state.entities[row].name, *values)
            return
        commands = np.column_stack([linear, lateral, angular]).astype(float)
        noisy, omni = self._robot_kinds()
        plain = np.isfinite(commands).all(axis=1) & ~noisy
        limited = self.commands.limited_rows(commands[plain])
        limited[~omni[plain], 1] = 0.0
        self.commands.update_rows(rows[plain], limited, self.sim_time)
        for robot, values in zip(np.flatnonzero(noisy), commands[noisy].tolist()):
            self.command(self.state.entities[rows[robot]].name, *values)

    def _robot_kinds(self):
        """Return which robots have motion noise and which are omni, in order (kept per roster)."""
        if self._kinds[:2] != (self.state, self.state.version):
            robots = [self.state.entities[row] for row in self.state.robot_rows]
            self._kinds = (self.state, self.state.version,
                           np.array([robot.motion_noise is not None for robot in robots],
                                    dtype=bool),
                           np.array([robot.description.kinematic.model == 'omni'
                                     for robot in robots], dtype=bool))
        return self._kinds[2:]

    def set_velocity(self, name: str, x: float, y: float, angular: float) -> None:
        """
        Set an entity moving at (x, y) m/s in the map frame while turning at angular rad/s.

        A robot takes it as a command (along its heading only); a moving obstacle keeps it
        until told otherwise; a static obstacle takes none but zero. RequestError otherwise.
        """
        self.set_state(name, self.pose(name), (x, y, angular))

    def set_state(self, name: str, pose: tuple, velocity: tuple) -> None:
        """Teleport an entity and set its velocity (as set_velocity), both or neither."""
        entity, index = self.entity(name), self.state.index(name)
        omni = entity.is_robot and entity.description.kinematic.model == 'omni'
        motion = motion_for(entity.category, pose[2], *velocity, self.settings, omni)
        self.teleport(name, pose)
        if entity.is_robot:
            self.command(name, motion.linear, motion.angular, motion.lateral)
        else:
            self.state.motion[index] = (motion.linear, motion.angular,
                                        np.nan if motion.heading is None else motion.heading)

    def step(self) -> None:
        """Advance every entity by dt: robots under their held commands, obstacles as set."""
        velocities = self.commands.current(self.sim_time)
        headings = None
        if len(self.state.robot_rows) < len(self.state):
            motion = self.state.motion
            sliding = ~np.isnan(motion[:, 2])
            if sliding.any():
                velocities[sliding, 0] = motion[sliding, 0]
                velocities[sliding, 2] = motion[sliding, 1]
                headings = motion[:, 2]
        moved = self.bodies.step(velocities[:, 0], velocities[:, 2], self.dt, headings,
                                 velocities[:, 1])
        self.state.stepped(moved, velocities)
        if self.odometer.noise.enabled:
            self.odometer.advance(self.dt)
        self.step_count += 1

    def reset(self, time: bool = True, state: bool = True, spawned: bool = True,
              seed: int | None = None) -> None:
        """
        Reset the simulation in part or whole, as if started again.

        spawned removes the entities added while running; state puts every other entity back
        at its start pose, standing still, with its odometry restarted; time restarts the
        clock, the schedules and the noise, so a run from here repeats the first; seed, if
        given, becomes the seed of every noise (sensors, odometry, motion) from then on. A
        state whose start poses now overlap raises PlacementError, and nothing changes.
        """
        if seed is not None:
            self.settings = replace(self.settings, sensor_seed=seed, odom_seed=seed,
                                    motion_seed=seed)
        keep = [entity for entity in self.state.entities
                if not (spawned and entity.spawned)]
        if state:
            self._rebuild(self.terrain, keep)
        else:
            for entity in [entity for entity in self.state.entities if entity not in keep]:
                self.remove(entity.name)
        if time:
            self._restart_time()

    def load_map(self, world: OccupancyMap | Terrain) -> None:
        """
        Replace the map (or a Terrain from survey()), as a standard LoadWorld does.

        Spawned entities go, the others return to their start poses, and time restarts.
        PlacementError if one of them does not fit there; nothing changes then.
        """
        terrain = world if isinstance(world, Terrain) else self.survey(world)
        self._rebuild(terrain, [entity for entity in self.state.entities
                                if not entity.spawned])
        self._restart_time()

    def _rebuild(self, terrain, entities):
        """Put entities at their start poses on this terrain, all or none of them."""
        bodies = Bodies(terrain.occupancy_map, self._largest, self.settings.integrator,
                        terrain.checker, self.settings.bodies_meet, StateTable())
        for entity in entities:
            try:
                bodies.add_body(entity.start_pose, entity.radius, entity.shape, entity)
            except PlacementError as error:
                raise PlacementError(f'{entity.name} cannot stand at its start pose: '
                                     f'{error}') from None
        self.terrain = terrain
        self._use(bodies)
