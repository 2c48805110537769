"""What the simulation holds besides the Bodies' arrays: its entities and their schedules."""

from dataclasses import dataclass, field, replace
import enum

from stdr_lite.core.robot_description import Noise, RobotDescription
from stdr_lite.core.setting_values import (OdometryNoise, SAFETY_ANGULAR_SPEED,
                                           SAFETY_LINEAR_SPEED, SENSOR_NOISE_MODES)

NANOSECONDS = 1_000_000_000


class RequestError(ValueError):
    """A request the simulation refuses (a name taken or unknown); nothing was changed."""


class NamespaceError(RequestError):
    """A robot's topic namespace that is no ROS namespace, or is another robot's."""


class Category(enum.Enum):
    """What an entity is: a robot with topics, or a circular obstacle that stays or moves."""

    ROBOT = 'robot'
    STATIC_OBSTACLE = 'static obstacle'
    MOVING_OBSTACLE = 'moving obstacle'


@dataclass(frozen=True)
class SimulationSettings:
    """
    How the world is stepped and measured; SI units.

    odom_rate_hz 0 is every step; a speed limit of 0 is none, as in STDR, short of the safety
    bound (commands.py); sensor_noise is one of SENSOR_NOISE_MODES; bodies_meet False lets bodies
    pass through each other unseen, each meeting only the walls (side-by-side independent
    episodes).
    """

    rate_hz: float = 50.0
    integrator: str = 'euler'
    max_linear_speed: float = 0.0
    max_angular_speed: float = 0.0
    safety_linear_speed: float = SAFETY_LINEAR_SPEED
    safety_angular_speed: float = SAFETY_ANGULAR_SPEED
    cmd_vel_timeout: float = 0.0
    sensor_seed: int = 0
    sensor_noise: str = 'auto'
    odom_rate_hz: float = 0.0
    odometry_noise: OdometryNoise = OdometryNoise()
    odom_seed: int = 0
    motion_seed: int = 0
    bodies_meet: bool = True

    def __post_init__(self):
        if self.sensor_noise not in SENSOR_NOISE_MODES:
            raise ValueError(f'sensor_noise must be one of {", ".join(SENSOR_NOISE_MODES)}, '
                             f'got {self.sensor_noise!r}')

    @property
    def safety(self) -> tuple[float, float]:
        """Return the safety bound on commands: (linear m/s, angular rad/s)."""
        return self.safety_linear_speed, self.safety_angular_speed

    def applies_sensor_noise(self, description: RobotDescription) -> bool:
        """Whether a robot of this description reads with the noise its file describes."""
        return self.sensor_noise == 'all' or (self.sensor_noise == 'auto'
                                              and not description.stdr_layout)

    def sensor_noise_note(self, description: RobotDescription) -> str:
        """Say whether a robot's described sensor noise is applied, and why; '' if it has none."""
        if not description.has_sensor_noise:
            return ''
        if self.applies_sensor_noise(description):
            return 'sensor noise as its file describes'
        if self.sensor_noise == 'none':
            return "its file's sensor noise not applied (sensor_noise none)"
        return ("its file's sensor noise not applied, as STDR reads its layout (sensor_noise "
                'all applies it)')


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
    """A laser or sonar and its reading times: every period, in the phase of schedule."""

    spec: object
    schedule: PeriodicSchedule

    def restart(self, now_ns: int) -> None:
        """Read first one period after now_ns."""
        self.schedule = PeriodicSchedule(self.schedule.period_ns, now_ns + self.schedule.period_ns)


@dataclass
class SimulatedEntity:
    """
    A robot or an obstacle, besides its state in the Bodies' arrays.

    start_pose is where a reset puts it back; spawned marks entities added while running,
    which a reset of spawned entities removes. A robot's topics sit under its namespace;
    motion_noise is the generator of its motion noise, if its kinematics has any.
    """

    name: str
    category: Category
    radius: float
    start_pose: tuple
    spawned: bool = False
    description: RobotDescription | None = None
    namespace: str = ''
    sensors: list = field(default_factory=list)
    motion_noise: object = None

    @property
    def is_robot(self) -> bool:
        return self.category is Category.ROBOT

    @property
    def shape(self) -> tuple | None:
        """Return a polygonal robot's corners (in its frame), or None for a circle."""
        return self.description.points or None if self.description is not None else None


def sensors_of(description: RobotDescription, now_ns: int,
               noisy: bool = True) -> list[ScheduledSensor]:
    """
    Return a description's lasers and sonars, each first due one period after now_ns.

    Unless noisy, they read without the noise the description gives them.
    """
    sensors = []
    for spec in description.lasers + description.sonars:
        spec = spec if noisy else replace(spec, noise=Noise())
        period_ns = round(NANOSECONDS / spec.frequency)
        sensors.append(ScheduledSensor(spec, PeriodicSchedule(period_ns, now_ns + period_ns)))
    return sensors


def sensor_groups(entities: list, last_step_ns: int) -> list[tuple[PeriodicSchedule, list]]:
    """
    Group the entities' sensors by reading times: [(schedule, [(name, [spec, ...]), ...])].

    Sensors of one period and phase read together; each group's schedule is first due at its
    first reading time after last_step_ns.
    """
    groups = {}
    for entity in entities:
        for sensor in entity.sensors:
            period_ns = sensor.schedule.period_ns
            key = (period_ns, sensor.schedule.next_due_ns % period_ns)
            members = groups.setdefault(key, {})
            members.setdefault(entity.name, []).append(sensor.spec)
    after = last_step_ns + 1
    return [(PeriodicSchedule(period_ns, after + (phase - after) % period_ns),
             list(members.items())) for (period_ns, phase), members in groups.items()]
