"""
Wheel odometry that can drift: every robot's odometry pose, its covariance, and its noise.

The model is the classic one of odometry error growing with the motion (variance proportional
to the distance travelled and the angle turned), so it does not depend on the step rate: a
step that moves by d metres and turns by a radians is measured as

    d' = d + N(0, distance**2 * |d|)
    a' = a + N(0, turn**2 * |a| + heading_per_distance**2 * |d|)

and integrated along the arc's mean heading; an omni robot's sideways distance takes the same
error as its forward one. The pose covariance is propagated with the same
model (linearised), so it grows as the robot drives and says how far the odometry may be off.
With every coefficient zero the odometry is the true pose, exactly, whatever happens to it.
"""

from dataclasses import dataclass
import math

from numba import njit
import numpy as np
from stdr_lite.core.kinematics import wrap
from stdr_lite.core.setting_values import OdometryNoise
from stdr_lite.core.state import StateTable


@dataclass(frozen=True)
class OdometryReading:
    """
    One robot's odometry: pose in its odom frame, measured velocity, and their spread.

    The velocity and its variance are (linear, lateral, angular): lateral is an omni robot's
    sideways velocity, zero for a unicycle's. exact marks a reading known to have no spread at
    all, so its zeros need no looking at.
    """

    pose: tuple
    velocity: tuple
    pose_covariance: np.ndarray
    velocity_variance: tuple
    exact: bool = False


NO_SPREAD = np.zeros((3, 3))
NO_SPREAD.flags.writeable = False


class Odometry:
    """
    The odometry of several robots, advanced together each step from the applied velocities.

    Each robot's odometry starts at its true pose (its odom frame coincides with the map at
    first) and, when noise is on, follows its own noisy measurements from then on: a teleport
    moves the robot, not its odometry, as carrying a real robot would. It is kept in the
    state's odometry columns (state.py).
    """

    def __init__(self, state: StateTable, noise: OdometryNoise = OdometryNoise(), seed: int = 0):
        self.state = state
        self.noise = noise
        self.reseed(seed)

    def reseed(self, seed: int) -> None:
        """Start the noise over, so a run from here repeats a run from the start."""
        self._rng = np.random.default_rng(seed)

    def advance(self, dt: float) -> None:
        """
        Measure the step just taken, in which each body moved at its applied velocity.

        Only drifting odometry is advanced: without noise the odometry is the true pose, which
        the simulation reads as it is (readings.py), and nothing calls this. The draws come from
        the odometry's own generator, in one order (forward, turn, then sideways if any body
        moved sideways); the rest is one compiled pass over the bodies (_measure).
        """
        state = self.state
        count = len(state)
        draws = np.zeros((count, 3))
        draws[:, 0] = self._rng.standard_normal(count)
        draws[:, 2] = self._rng.standard_normal(count)
        if state.applied[:, 1].any():
            draws[:, 1] = self._rng.standard_normal(count)
        for name in ('odometry_pose', 'odometry_covariance', 'odometry_velocity',
                     'odometry_variance'):
            setattr(state, name, getattr(state, name).copy())
        _measure(state.applied, float(dt), self.noise.distance, self.noise.turn,
                 self.noise.heading_per_distance, draws, state.odometry_pose,
                 state.odometry_covariance, state.odometry_velocity, state.odometry_variance)

    def reading(self, index: int) -> OdometryReading:
        state = self.state
        x, y, theta = state.odometry_pose[index].tolist()
        return OdometryReading((x, y, theta), tuple(state.odometry_velocity[index].tolist()),
                               state.odometry_covariance[index].copy(),
                               tuple(state.odometry_variance[index].tolist()))


@njit(cache=True)
def _measure(applied, dt, distance_noise, turn_noise, heading_noise, draws, pose, covariance,
             velocity, variance):
    """
    Measure each body's step with noise and integrate it along its mean heading, in place.

    The pose covariance P is carried along as M P M' + N V N', M the step's Jacobian in the
    pose, N in the measured motion (forward, sideways, turn), V its variances.
    """
    for body in range(applied.shape[0]):
        forward, sideways = applied[body, 0] * dt, applied[body, 1] * dt
        turn = applied[body, 2] * dt
        spread = np.empty(3)
        spread[0] = distance_noise ** 2 * abs(forward)
        spread[1] = distance_noise ** 2 * abs(sideways)
        spread[2] = (turn_noise ** 2 * abs(turn)
                     + heading_noise ** 2 * (abs(forward) + abs(sideways)))
        forward += math.sqrt(spread[0]) * draws[body, 0]
        sideways += math.sqrt(spread[1]) * draws[body, 1]
        turn += math.sqrt(spread[2]) * draws[body, 2]
        heading = pose[body, 2] + 0.5 * turn
        cos_heading, sin_heading = math.cos(heading), math.sin(heading)
        step_x = forward * cos_heading - sideways * sin_heading
        step_y = forward * sin_heading + sideways * cos_heading
        motion = np.eye(3)
        motion[0, 2], motion[1, 2] = -step_y, step_x
        noise = np.eye(3)
        noise[0, 0], noise[1, 0], noise[0, 1], noise[1, 1] = (cos_heading, sin_heading,
                                                              -sin_heading, cos_heading)
        noise[0, 2], noise[1, 2] = -0.5 * step_y, 0.5 * step_x
        carried = _sandwich(motion, covariance[body])
        added = _sandwich(noise, np.diag(spread))
        for row in range(3):
            for column in range(3):
                covariance[body, row, column] = carried[row, column] + added[row, column]
        pose[body, 0] += step_x
        pose[body, 1] += step_y
        pose[body, 2] = wrap(pose[body, 2] + turn)
        velocity[body, 0], velocity[body, 1], velocity[body, 2] = (forward / dt,
                                                                   sideways / dt, turn / dt)
        variance[body] = spread / dt ** 2


@njit(cache=True)
def _sandwich(outer, inner):
    """Return outer @ inner @ outer.T, for 3 x 3 matrices."""
    product = np.zeros((3, 3))
    for row in range(3):
        for column in range(3):
            total = 0.0
            for left in range(3):
                for right in range(3):
                    total += outer[row, left] * inner[left, right] * outer[column, right]
            product[row, column] = total
    return product
