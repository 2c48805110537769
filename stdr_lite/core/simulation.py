"""
The simulation: robots by name in one world, stepped at a fixed rate. No ROS here.

Everything kept per robot (pose and radius in the World, the held command, the velocity last
applied, the sensors' schedule) is added, removed and renumbered here in one place, so those
structures never fall out of step. The stdr_lite node only turns messages into calls of this
class and its results into messages; tests and benchmarks drive it directly.
"""

from contextlib import contextmanager
from dataclasses import dataclass, field
import enum
import math
from typing import Iterable

import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.pose import compose, invert
from simple_robot_control.validation import compact, ros_name_problem
from stdr_lite.core.commands import CommandBuffer
from stdr_lite.core.odometry import Odometry, OdometryNoise, OdometryReading
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.sensors import RangeFinder, read_sensors
from stdr_lite.core.world import PlacementError, World

NANOSECONDS = 1_000_000_000
# Footprints up to this radius can be added while running, besides those in the start list.
LARGEST_ADDED_RADIUS = 0.5


class RequestError(ValueError):
    """A request the simulation refuses (a name taken or unknown); nothing was changed."""


class CommandOutcome(enum.Enum):
    """What became of a velocity command."""

    APPLIED = 'applied'
    CLAMPED = 'clamped to the speed limits'
    IGNORED = 'ignored: not finite'


@dataclass(frozen=True)
class SimulationSettings:
    """How the world is stepped and measured; SI units. odom_rate_hz 0 is every step."""

    rate_hz: float = 50.0
    integrator: str = 'euler'
    max_linear_speed: float = 2.0
    max_angular_speed: float = math.pi
    cmd_vel_timeout: float = 0.0
    sensor_seed: int = 0
    odom_rate_hz: float = 0.0
    odometry_noise: OdometryNoise = OdometryNoise()
    odom_seed: int = 0


class PeriodicSchedule:
    """Falls due once per period of sim time, from first_due_ns on, whatever the step rate."""

    def __init__(self, period_ns: int, first_due_ns: int):
        self.period_ns = period_ns
        self.next_due_ns = first_due_ns

    def due(self, now_ns: int) -> bool:
        """Whether the schedule falls due at now_ns; if so, it moves on to the next period."""
        if now_ns < self.next_due_ns:
            return False
        self.next_due_ns += self.period_ns * (1 + (now_ns - self.next_due_ns) // self.period_ns)
        return True


@dataclass
class ScheduledSensor:
    """A laser or sonar and when it next reads."""

    spec: object
    schedule: PeriodicSchedule


@dataclass
class SimulatedRobot:
    """What the simulation knows of a robot besides its state arrays."""

    name: str
    description: RobotDescription
    sensors: list = field(default_factory=list)


class Simulation:
    """
    Unicycle robots in one map, stepped together every dt = 1/rate_hz simulated seconds.

    Each robot holds its last valid command until the next (as STDR does), or stops once the
    command is older than cmd_vel_timeout when that is positive. For lockstep runs the
    simulation also keeps which robots have answered the latest state with a command.
    """

    def __init__(self, occupancy_map: OccupancyMap,
                 settings: SimulationSettings = SimulationSettings(),
                 robots: Iterable[RobotEntry] = ()):
        robots = list(robots)
        self.settings = settings
        self.dt_ns = round(NANOSECONDS / settings.rate_hz)
        largest = max([LARGEST_ADDED_RADIUS] + [entry.description.radius for entry in robots])
        self.world = World(occupancy_map, largest, settings.integrator)
        self._finder = RangeFinder(occupancy_map)
        self._noise = np.random.default_rng(settings.sensor_seed)
        self._commands = CommandBuffer(0, settings.max_linear_speed, settings.max_angular_speed,
                                       settings.cmd_vel_timeout)
        self._applied = (np.zeros(0), np.zeros(0))
        self._odometry = Odometry(settings.odometry_noise, settings.odom_seed)
        odometry_period = (self.dt_ns if settings.odom_rate_hz <= 0.0
                           else round(NANOSECONDS / settings.odom_rate_hz))
        self._odometry_schedule = PeriodicSchedule(odometry_period, 0)
        self._robots = []
        self._indices = {}
        self._unanswered = set()
        self.step_count = 0
        for entry in robots:
            try:
                self.add_robot(entry)
            except (PlacementError, RequestError) as error:
                raise type(error)(f'{entry.name} in {occupancy_map.source}: {error}') from None

    @property
    def occupancy_map(self) -> OccupancyMap:
        return self.world.map

    @property
    def dt(self) -> float:
        """Return the step in simulated seconds."""
        return self.dt_ns / NANOSECONDS

    @property
    def time_ns(self) -> int:
        """Return the simulated nanoseconds since start."""
        return self.step_count * self.dt_ns

    @property
    def sim_time(self) -> float:
        """Return the simulated seconds since start."""
        return self.time_ns / NANOSECONDS

    @property
    def names(self) -> list[str]:
        """Return the robots' names, in the order they were added."""
        return [robot.name for robot in self._robots]

    def __contains__(self, name: str) -> bool:
        return name in self._indices

    def robot(self, name: str) -> SimulatedRobot:
        return self._robots[self._index(name)]

    def pose(self, name: str) -> tuple[float, float, float]:
        """Return the robot's (x, y, theta) in the map frame."""
        x, y, theta = self.world.poses[self._index(name)].tolist()
        return x, y, theta

    def applied_velocity(self, name: str) -> tuple[float, float]:
        """Return the (linear, angular) velocity of the last step: zero while blocked."""
        index = self._index(name)
        return float(self._applied[0][index]), float(self._applied[1][index])

    def default_name(self) -> str:
        """Return robot<K> with the smallest K not taken."""
        return next(f'robot{k}' for k in range(len(self._robots) + 1)
                    if f'robot{k}' not in self._indices)

    def add_robot(self, entry: RobotEntry) -> None:
        """
        Place a robot with its description at its pose.

        Raises RequestError for a bad or taken name and PlacementError for a pose off the map,
        in a wall or on another robot; either way nothing changes.
        """
        problem = ros_name_problem(entry.name, 'a robot name')
        if problem is not None:
            raise RequestError(problem)
        if entry.name in self._indices:
            raise RequestError(f'a robot named {entry.name} exists already')
        for spec in entry.description.lasers + entry.description.sonars:
            if spec.frequency > self.settings.rate_hz:
                raise RequestError(f'sensor {spec.frame_id} reads at {compact(spec.frequency)} '
                                   f'Hz, faster than the simulation steps (rate_hz '
                                   f'{compact(self.settings.rate_hz)})')
        with self._naming_overlaps():
            self.world.add_robot(entry.pose, entry.description.radius)
        self._commands.add_robot()
        self._applied = tuple(np.append(values, 0.0) for values in self._applied)
        self._odometry.add_robot(entry.pose)
        sensors = []
        for spec in entry.description.lasers + entry.description.sonars:
            period_ns = round(NANOSECONDS / spec.frequency)
            sensors.append(ScheduledSensor(spec, PeriodicSchedule(period_ns,
                                                                  self.time_ns + period_ns)))
        self._robots.append(SimulatedRobot(entry.name, entry.description, sensors))
        self._renumber()

    def remove_robot(self, name: str) -> None:
        """Take a robot out; the robots after it move down one index."""
        index = self._index(name)
        self.world.remove_robot(index)
        self._commands.remove_robot(index)
        self._applied = tuple(np.delete(values, index) for values in self._applied)
        self._odometry.remove_robot(index)
        del self._robots[index]
        self._unanswered.discard(name)
        self._renumber()

    def teleport(self, name: str, pose: tuple[float, float, float]) -> None:
        """
        Move a robot to pose, or raise PlacementError and leave it where it is.

        Drifting odometry does not notice (the robot was carried): map -> odom takes the jump.
        """
        index = self._index(name)
        with self._naming_overlaps():
            self.world.move_robot(index, pose)

    def command(self, name: str, linear: float, angular: float) -> CommandOutcome:
        """Hold (linear m/s, angular rad/s) for the robot from now on, clamped to the limits."""
        index = self._index(name)
        if not (math.isfinite(linear) and math.isfinite(angular)):
            return CommandOutcome.IGNORED
        clamped = self._commands.exceeds_limits(linear, angular)
        self._commands.update(index, linear, angular, self.sim_time)
        return CommandOutcome.CLAMPED if clamped else CommandOutcome.APPLIED

    def step(self) -> None:
        """Advance every robot by dt under its held command."""
        linear, angular = self._commands.current(self.sim_time)
        self._applied = self.world.step(linear, angular, self.dt)
        if self._odometry.noise.enabled:
            self._odometry.advance(self.world.poses, *self._applied, self.dt)
        self.step_count += 1

    def odometry_due(self) -> bool:
        """Whether odometry is to be published at this step (every 1/odom_rate_hz of sim time)."""
        return self._odometry_schedule.due(self.time_ns)

    def odometry(self, name: str) -> OdometryReading:
        """
        Return the robot's odometry: its pose in its odom frame and its measured velocity.

        Without noise these are the true pose and the applied velocity, with zero spread.
        """
        if self._odometry.noise.enabled:
            return self._odometry.reading(self._index(name))
        return self.ground_truth(name)

    def ground_truth(self, name: str) -> OdometryReading:
        """Return the robot's true pose in the map frame and its applied velocity, exactly."""
        return OdometryReading(self.pose(name), self.applied_velocity(name), np.zeros((3, 3)),
                               (0.0, 0.0))

    def map_to_odom(self, name: str) -> tuple[float, float, float]:
        """
        Return the transform from the map frame to the robot's odom frame.

        It is what makes map -> odom -> base_link the true pose, as a perfect localiser would
        publish it: the identity while the odometry is exact.
        """
        if not self._odometry.noise.enabled:
            return 0.0, 0.0, 0.0
        return compose(self.pose(name), invert(self.odometry(name).pose))

    def due_sensors(self) -> list[tuple[str, object]]:
        """
        Return (robot name, sensor spec) for each sensor due to read at this step.

        Each sensor is due once per period of sim time; its schedule moves on whether or not
        the caller then reads it, so an unread sensor costs nothing.
        """
        return [(robot.name, sensor.spec) for robot in self._robots for sensor in robot.sensors
                if sensor.schedule.due(self.time_ns)]

    def read_sensors(self, jobs: list[tuple[str, object]]) -> list:
        """Read sensors at the current poses: a laser's ranges or a sonar's range, per job."""
        return read_sensors(self._finder, self.world.poses, self.world.radii,
                            [(self._index(name), spec) for name, spec in jobs], self._noise)

    def expect_answers(self) -> None:
        """Lockstep: from now on, wait for a command from every robot before stepping."""
        self._unanswered = set(self._indices)

    def answer(self, name: str) -> bool:
        """Lockstep: note that the robot answered; return whether its answer was awaited."""
        if name not in self._unanswered:
            return False
        self._unanswered.discard(name)
        return True

    @property
    def awaiting_answers(self) -> bool:
        """Lockstep: whether some robot has not answered the latest state yet."""
        return bool(self._unanswered)

    def _index(self, name: str) -> int:
        try:
            return self._indices[name]
        except KeyError:
            raise RequestError(f'no robot named {name!r}') from None

    @contextmanager
    def _naming_overlaps(self):
        """Name the robot in the way, where the World can only number it."""
        try:
            yield
        except PlacementError as error:
            if error.overlapped is None:
                raise
            other = self._robots[error.overlapped].name
            raise PlacementError(str(error).replace(f'robot {error.overlapped}', other),
                                 overlapped=error.overlapped) from None

    def _renumber(self) -> None:
        self._indices = {robot.name: index for index, robot in enumerate(self._robots)}
