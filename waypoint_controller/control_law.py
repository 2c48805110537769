"""
The waypoint control law: pose in, (v, omega) out. Pure Python, no ROS.

For each waypoint the law plans the time-optimal path into its goal set (planner.py: a
Reeds-Shepp path at full speed, cusps included, or a full-rate turn when the position is
already close), choosing the end pose that is quickest counting the leg after it, so that
intermediate waypoints are passed at speed. It then tracks that plan: the plan's own velocities
are fed forward and the lab's two PIDs, on heading and on distance along the heading, correct
the error against the plan's reference pose. When the pose strays from the plan (a disturbance,
drifting odometry, late commands) the law plans again from where the robot is.
"""

from collections.abc import Callable
import math

from simple_robot_control.pose import wrap_angle as wrap
from waypoint_controller.config import ControllerConfig
from waypoint_controller.pid import lab_pids
from waypoint_controller.planner import fastest_plan, Limits, Plan, plan_to_goal_set
from waypoint_lab.waypoints import Waypoint

# Straying from the reference pose by more than this much, or by more than STRAY_PERIODS of
# one control period's motion, means planning again, to the same end pose: smaller errors are
# the PIDs' to correct, so a command that lands a period late does not set off a new plan.
# Straying RECHOOSE_DISTANCE means choosing the end pose again too.
REPLAN_DISTANCE = 0.02
REPLAN_ANGLE = math.radians(2.0)
STRAY_PERIODS = 1.5
RECHOOSE_DISTANCE = 0.1


def plan_limits(config: ControllerConfig) -> Limits:
    """Return the limits and goal set the planner plans with under config."""
    return Limits(config.max_linear_speed, config.max_angular_speed, config.distance_tolerance,
                  config.angle_tolerance)


def _clamp(value, limit):
    return max(-limit, min(limit, value))


def _as_pose(waypoint):
    return None if waypoint is None else (waypoint.x, waypoint.y, waypoint.theta)


class PoseController:
    """
    Drives into one waypoint's goal set; call start() for each new waypoint, then command().

    is_free(plan), when given, vetoes plans (a footprint crossing a wall); with every plan
    vetoed the robot stops and plan is None until the pose, the map or the configuration
    changes: planning again from the same pose would give the same answer, and a search of the
    whole goal set costs a tenth of a second (the stall timeout ends such a run).
    """

    def __init__(self, config=ControllerConfig(), is_free=None):
        config.validate()
        self.config = config
        self.is_free = is_free
        self._heading_pid, self._distance_pid = lab_pids(config)
        self.waypoint = self.next_waypoint = self.plan = None
        self.replans = 0
        self._elapsed = 0.0
        # Where planning last found every plan vetoed; None while not blocked.
        self._blocked_at = None
        # How the robot was last told to go (+1 forwards, counterclockwise; 0 neither): a new
        # plan to the same end pose sets off the same way unless another is much quicker.
        self._direction = self._turn = 0

    def reconfigure(self, config: ControllerConfig) -> None:
        """Take new limits, tolerances and gains; the next command plans anew with them."""
        config.validate()
        self.config = config
        self._heading_pid.retune(config.heading_kp, config.heading_ki, config.heading_kd,
                                 config.max_angular_speed)
        self._distance_pid.retune(config.distance_kp, config.distance_ki, config.distance_kd,
                                  config.max_linear_speed)
        self.plan_again()

    def plan_again(self) -> None:
        """Drop the plan: the next command plans anew (new limits, or a new map)."""
        self.plan = None
        self._blocked_at = None

    def start(self, pose: tuple, waypoint: Waypoint, next_waypoint: Waypoint | None = None,
              target: tuple | None = None) -> None:
        """
        Aim at a new waypoint from pose; next_waypoint, if any, is counted in choosing how.

        A target pose, if given, is aimed at instead of the quickest pose of the goal set.
        """
        self.waypoint, self.next_waypoint, self.target = waypoint, next_waypoint, target
        self._plan_from(pose, rechoose=target is None)

    def _plan_from(self, pose, rechoose):
        self._heading_pid.reset()
        self._distance_pid.reset()
        self._elapsed = 0.0
        limits = plan_limits(self.config)
        plan = None
        if not rechoose:
            plan = fastest_plan(pose, self.target, limits, self._direction, self._turn)
            if self.is_free is not None and not self.is_free(plan):
                plan = None
        if plan is None:
            plan = plan_to_goal_set(pose, _as_pose(self.waypoint), limits,
                                    _as_pose(self.next_waypoint), self.is_free)
            if plan is not None:
                self.target = plan.pose_at(plan.duration)
        self.plan = plan
        self._blocked_at = None if plan is not None else pose

    def command(self, pose: tuple, dt: float) -> tuple[float, float]:
        """Return (linear, angular) velocity for the next dt seconds."""
        self._replan_if_astray(pose, dt)
        if self.plan is None:
            return 0.0, 0.0
        config = self.config
        reference = self.plan.pose_at(self._elapsed)
        ahead = self.plan.pose_at(self._elapsed + dt)
        self._elapsed += dt
        feed_angular = wrap(ahead[2] - reference[2]) / dt
        half_turn = 0.5 * feed_angular * dt
        middle = reference[2] + half_turn
        chord = ((ahead[0] - reference[0]) * math.cos(middle)
                 + (ahead[1] - reference[1]) * math.sin(middle))
        feed_linear = chord / (dt * (math.sin(half_turn) / half_turn if half_turn else 1.0))
        x, y, theta = pose
        heading_error = wrap(reference[2] - theta)
        distance_error = ((reference[0] - x) * math.cos(theta)
                          + (reference[1] - y) * math.sin(theta))
        angular = feed_angular + self._heading_pid.update(
            heading_error, dt, kp=min(config.heading_kp, 0.9 / dt))
        linear = feed_linear + self._distance_pid.update(
            distance_error, dt, kp=min(config.distance_kp, 0.9 / dt))
        linear = _clamp(linear, config.max_linear_speed)
        angular = _clamp(angular, config.max_angular_speed)
        if abs(linear) > 1e-9:
            self._direction = 1 if linear > 0.0 else -1
        # A turn at half the rate or more is turning; less is driving straight.
        self._turn = (0 if abs(angular) < 0.5 * config.max_angular_speed
                      else 1 if angular > 0.0 else -1)
        return linear, angular

    def _replan_if_astray(self, pose, dt):
        if self.plan is None:
            if self._blocked_at is None or not _near(pose, self._blocked_at):
                self._plan_from(pose, rechoose=True)
            return
        reference = self.plan.pose_at(self._elapsed)
        stray = math.hypot(pose[0] - reference[0], pose[1] - reference[1])
        spent = self._elapsed >= self.plan.duration
        distance_limit = max(REPLAN_DISTANCE, STRAY_PERIODS * self.config.max_linear_speed * dt)
        angle_limit = max(REPLAN_ANGLE, STRAY_PERIODS * self.config.max_angular_speed * dt)
        if spent or stray > distance_limit or abs(wrap(pose[2] - reference[2])) > angle_limit:
            self.replans += 1
            self._plan_from(pose, rechoose=spent or stray > RECHOOSE_DISTANCE)


def _near(pose, other):
    """Whether two poses are within the distances that call for no new plan."""
    return (math.hypot(pose[0] - other[0], pose[1] - other[1]) <= REPLAN_DISTANCE
            and abs(wrap(pose[2] - other[2])) <= REPLAN_ANGLE)


class PlannedLaw:
    """
    The lab's answer as a control law (waypoint_lab/lifecycle.py): plan into each goal set.

    is_free vetoes plans (see PoseController); targets, if given, are the end poses to aim at,
    one per waypoint, instead of the ones the planner would choose (to replay a given plan).
    """

    def __init__(self, waypoints, config=ControllerConfig(), is_free=None, targets=None):
        self.waypoints = list(waypoints)
        self.targets = targets
        self.controller = PoseController(config, is_free)

    @property
    def config(self) -> ControllerConfig:
        return self.controller.config

    def avoid(self, is_free: Callable[[Plan], bool]) -> None:
        """Veto plans with is_free(plan) from now on (a new map): the next command re-plans."""
        self.controller.is_free = is_free
        self.controller.plan_again()

    def reconfigure(self, config: ControllerConfig) -> None:
        """Use new limits, tolerances and gains from the next command on."""
        self.controller.reconfigure(config)

    def aim(self, pose: tuple, index: int) -> None:
        """Plan from pose into waypoint index's goal set, counting the leg after it."""
        following = self.waypoints[index + 1] if index + 1 < len(self.waypoints) else None
        self.controller.start(pose, self.waypoints[index], following,
                              None if self.targets is None else self.targets[index])

    def command(self, pose: tuple, dt: float) -> tuple[float, float]:
        """Return (linear, angular) velocity for the next dt seconds."""
        return self.controller.command(pose, dt)
