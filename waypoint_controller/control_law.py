"""
The waypoint control law: pose in, (v, omega) out. Pure Python, no ROS.

Far from the goal a heading PID steers towards a guidance direction: the line of sight to the
goal, bent towards the goal's heading axis so that the robot arrives already facing the goal
heading and passes intermediate waypoints without stopping. For each waypoint the law picks
forward or backward travel, how strongly to bend (the approach gain, 0 for none) and whether
to pivot towards the goal before driving, and how far (the quick way to sidestep), by
simulating itself for every combination and keeping the quickest. The bend stays below 90 degrees,
so the robot always closes in on the goal. Speed comes from a distance PID, at full speed while
turning, capped so that the goal never falls inside the turning circle (so the robot never
orbits it), and zero while the goal is more than 90 degrees off the direction of travel. Well
inside the distance tolerance the law rotates in place at full rate with deadbeat braking, and
leaves that mode only if the robot is pushed out past a larger radius (hysteresis).
"""

from dataclasses import dataclass
import math

from waypoint_controller.pid import PID


APPROACH_GAINS = (0.0, 0.25, 0.75, 2.0)
PIVOT_THRESHOLDS = (None, math.radians(5.0), math.radians(30.0), math.radians(60.0))
PREDICTION_STEP = 0.1
PREDICTION_HORIZON = 60.0


def _arc(pose, linear, angular, dt):
    """
    Exact constant-velocity arc step for one robot: the model the law predicts with.

    Same formula as stdr_lite.core.kinematics.arc_step, in scalar math because a prediction takes
    thousands of single-robot steps, where numpy's per-call cost would dominate.
    """
    x, y, theta = pose
    half_turn = 0.5 * angular * dt
    chord = linear * dt * (math.sin(half_turn) / half_turn if half_turn else 1.0)
    return (x + chord * math.cos(theta + half_turn), y + chord * math.sin(theta + half_turn),
            theta + angular * dt)


def wrap(angle):
    """Wrap an angle to (-pi, pi]."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped


@dataclass(frozen=True)
class ControllerConfig:
    """Limits, goal set and gains; SI units and radians."""

    max_linear_speed: float = 0.5
    max_angular_speed: float = 1.0
    distance_tolerance: float = 0.1
    angle_tolerance: float = math.radians(5.0)
    heading_kp: float = 4.0
    heading_ki: float = 0.5
    heading_kd: float = 0.0
    distance_kp: float = 5.0
    distance_ki: float = 0.0
    distance_kd: float = 0.0
    rotate_radius: float = 0.5
    resume_radius: float = 0.9

    def validate(self):
        """Raise ValueError naming the first field out of range."""
        for name in ('max_linear_speed', 'max_angular_speed', 'distance_tolerance',
                     'angle_tolerance', 'heading_kp', 'distance_kp'):
            if not getattr(self, name) > 0.0:
                raise ValueError(f'{name} must be positive, got {getattr(self, name)}')
        for name in ('heading_ki', 'heading_kd', 'distance_ki', 'distance_kd'):
            if not getattr(self, name) >= 0.0:
                raise ValueError(f'{name} must be >= 0, got {getattr(self, name)}')
        if not 0.0 < self.rotate_radius < self.resume_radius <= 1.0:
            raise ValueError('need 0 < rotate_radius < resume_radius <= 1 (fractions of '
                             f'distance_tolerance), got {self.rotate_radius} and '
                             f'{self.resume_radius}')


def in_goal_set(pose, waypoint, config):
    """Whether pose (x, y, theta) lies in the waypoint's goal set, as the lab defines it."""
    x, y, theta = pose
    return (math.hypot(waypoint.x - x, waypoint.y - y) <= config.distance_tolerance
            and abs(wrap(theta - waypoint.theta)) <= config.angle_tolerance)


class PoseController:
    """Drives to one waypoint pose; call start() for each new waypoint, then command()."""

    def __init__(self, config=ControllerConfig()):
        config.validate()
        self.config = config
        self._heading_pid = PID(config.heading_kp, config.heading_ki, config.heading_kd,
                                config.max_angular_speed)
        self._distance_pid = PID(config.distance_kp, config.distance_ki, config.distance_kd,
                                 config.max_linear_speed)
        self.waypoint = None

    def reconfigure(self, config: ControllerConfig) -> None:
        """Take new limits, tolerances and gains; the manoeuvre under way carries on."""
        config.validate()
        self.config = config
        self._heading_pid.retune(config.heading_kp, config.heading_ki, config.heading_kd,
                                 config.max_angular_speed)
        self._distance_pid.retune(config.distance_kp, config.distance_ki, config.distance_kd,
                                  config.max_linear_speed)
        self.backward = False
        self.rotating = False
        self.pivoting = None

    def start(self, pose, waypoint, backward=None, approach_gain=None, pivot=None):
        """
        Aim at a new waypoint from pose.

        Unless given, the direction of travel, the approach gain and the pivot (None, or how
        far off the goal may be before driving starts: the robot first turns in place until
        it is) are chosen by simulating this law for each candidate and keeping the quickest.
        """
        self.waypoint = waypoint
        self._heading_pid.reset()
        self._distance_pid.reset()
        self.rotating = False
        if backward is None:
            backward, approach_gain, pivot = self._quickest_manoeuvre(pose)
        self.backward = backward
        self.approach_gain = approach_gain
        self.pivoting = pivot

    def _quickest_manoeuvre(self, pose):
        candidates = sorted(((backward, gain, pivot) for backward in (False, True)
                             for gain in APPROACH_GAINS for pivot in PIVOT_THRESHOLDS),
                            key=lambda candidate: self._travel_time(pose, candidate[0]))
        best, best_time = candidates[0], math.inf
        for candidate in candidates:
            predicted = self._predict(pose, *candidate, limit=best_time)
            if predicted < best_time:
                best, best_time = candidate, predicted
        return best

    def _predict(self, pose, backward, gain, pivot, limit):
        """Seconds this law would take to the goal set with these choices (inf past limit)."""
        model = PoseController(self.config)
        model.start(pose, self.waypoint, backward, gain, pivot)
        elapsed = 0.0
        while not in_goal_set(pose, self.waypoint, self.config):
            if elapsed >= min(limit, PREDICTION_HORIZON):
                return math.inf
            linear, angular = model.command(pose, PREDICTION_STEP)
            pose = _arc(pose, linear, angular, PREDICTION_STEP)
            elapsed += PREDICTION_STEP
        return elapsed

    def _travel_time(self, pose, backward):
        """Estimate the time to the waypoint: driving plus the turning it needs."""
        x, y, theta = pose
        flip = math.pi if backward else 0.0
        distance = math.hypot(self.waypoint.x - x, self.waypoint.y - y)
        line_of_sight = math.atan2(self.waypoint.y - y, self.waypoint.x - x)
        turning = (abs(wrap(line_of_sight - theta - flip))
                   + abs(wrap(self.waypoint.theta + flip - line_of_sight)))
        return (distance / self.config.max_linear_speed
                + turning / self.config.max_angular_speed)

    def command(self, pose, dt):
        """Return (linear, angular) velocity for the next dt seconds."""
        config = self.config
        x, y, theta = pose
        goal = self.waypoint
        distance = math.hypot(goal.x - x, goal.y - y)
        if distance <= config.rotate_radius * config.distance_tolerance:
            self.rotating = True
        elif distance > config.resume_radius * config.distance_tolerance:
            self.rotating = False
        if self.rotating:
            return 0.0, self._rotate_in_place(wrap(goal.theta - theta), dt)
        flip = math.pi if self.backward else 0.0
        travel_heading = theta + flip
        line_of_sight = math.atan2(goal.y - y, goal.x - x)
        if self.pivoting is not None:
            sight_error = wrap(line_of_sight - travel_heading)
            if abs(sight_error) > self.pivoting:
                return 0.0, self._rotate_in_place(sight_error, dt)
            self.pivoting = None
        lead = math.atan(self.approach_gain * wrap(line_of_sight - goal.theta - flip))
        heading_error = wrap(line_of_sight + lead - travel_heading)
        angular = self._heading_pid.update(heading_error, dt,
                                           kp=min(config.heading_kp, 0.9 / dt))
        speed = self._distance_pid.update(distance, dt, kp=min(config.distance_kp, 0.9 / dt))
        sight_error = wrap(line_of_sight - travel_heading)
        if abs(sight_error) >= 0.5 * math.pi:
            speed = 0.0
        elif sight_error != 0.0:
            speed = min(speed, config.max_angular_speed * distance
                        / (2.0 * abs(math.sin(sight_error))))
        return (-speed if self.backward else speed), angular

    def _rotate_in_place(self, error, dt):
        """Turn at full rate, braking so the last step lands on the goal heading."""
        return math.copysign(min(self.config.max_angular_speed, abs(error) / dt), error)


@dataclass(frozen=True)
class FollowerStep:
    """One control step: the command, the waypoints reached at this pose, and completion."""

    linear: float
    angular: float
    reached: tuple
    finished: bool


class CourseFollower:
    """Takes a robot through waypoints in order; each is reached on entering its goal set."""

    def __init__(self, waypoints, config=ControllerConfig()):
        if not waypoints:
            raise ValueError('a course needs at least one waypoint')
        self.waypoints = list(waypoints)
        self.config = config
        self._controller = PoseController(config)
        self.next_index = 0
        self._started = False

    def reconfigure(self, config: ControllerConfig) -> None:
        """Use new limits, tolerances and gains from the next check or command on."""
        self._controller.reconfigure(config)
        self.config = config

    @property
    def finished(self):
        return self.next_index >= len(self.waypoints)

    @property
    def current(self):
        """Return the waypoint being driven to, or None when finished."""
        return None if self.finished else self.waypoints[self.next_index]

    def errors(self, pose):
        """Return (distance, wrapped heading error) from pose to the current waypoint."""
        goal = self.current
        return (math.hypot(goal.x - pose[0], goal.y - pose[1]), wrap(goal.theta - pose[2]))

    def check(self, pose):
        """Advance past every waypoint whose goal set contains pose; return their indices."""
        reached = []
        if not self._started:
            self._controller.start(pose, self.waypoints[0])
            self._started = True
        while not self.finished and in_goal_set(pose, self.current, self.config):
            reached.append(self.next_index)
            self.next_index += 1
            if not self.finished:
                self._controller.start(pose, self.current)
        return tuple(reached)

    def update(self, pose, dt):
        """Check the goal set at pose, then return the command for the next dt seconds."""
        reached = self.check(pose)
        if self.finished:
            return FollowerStep(0.0, 0.0, reached, True)
        linear, angular = self._controller.command(pose, dt)
        return FollowerStep(linear, angular, reached, False)
