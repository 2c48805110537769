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

import numpy as np
from simple_robot_control.pose import wrap_angle
from stdr_lite.core.setting_values import OdometryNoise
from stdr_lite.core.state import WorldState


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

    def __init__(self, state: WorldState, noise: OdometryNoise = OdometryNoise(), seed: int = 0):
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
        the simulation reads as it is (readings.py), and nothing calls this.
        """
        state = self.state
        distance, sideways = state.applied[:, 0] * dt, state.applied[:, 1] * dt
        turn = state.applied[:, 2] * dt
        variance_distance = self.noise.distance ** 2 * np.abs(distance)
        variance_sideways = self.noise.distance ** 2 * np.abs(sideways)
        variance_turn = (self.noise.turn ** 2 * np.abs(turn)
                         + self.noise.heading_per_distance ** 2 * (np.abs(distance)
                                                                   + np.abs(sideways)))
        count = len(turn)
        distance = distance + np.sqrt(variance_distance) * self._rng.standard_normal(count)
        turn = turn + np.sqrt(variance_turn) * self._rng.standard_normal(count)
        if sideways.any():
            sideways = sideways + np.sqrt(variance_sideways) * self._rng.standard_normal(count)
        variances = np.column_stack([variance_distance, variance_sideways, variance_turn])
        self._propagate(distance, sideways, turn, variances)
        state.odometry_velocity = np.column_stack([distance, sideways, turn]) / dt
        state.odometry_variance = variances / dt ** 2

    def _propagate(self, distance, sideways, turn, variances):
        """Integrate the measured step along its mean heading and carry the covariance along."""
        state = self.state
        heading = state.odometry_pose[:, 2] + 0.5 * turn
        cos_heading, sin_heading = np.cos(heading), np.sin(heading)
        step_x = distance * cos_heading - sideways * sin_heading
        step_y = distance * sin_heading + sideways * cos_heading
        count = len(distance)
        motion = np.tile(np.eye(3), (count, 1, 1))
        motion[:, 0, 2], motion[:, 1, 2] = -step_y, step_x
        noise = np.zeros((count, 3, 3))
        noise[:, 0, 0], noise[:, 1, 0] = cos_heading, sin_heading
        noise[:, 0, 1], noise[:, 1, 1] = -sin_heading, cos_heading
        noise[:, 0, 2], noise[:, 1, 2] = -0.5 * step_y, 0.5 * step_x
        noise[:, 2, 2] = 1.0
        spread = np.zeros((count, 3, 3))
        spread[:, 0, 0], spread[:, 1, 1], spread[:, 2, 2] = variances.T
        state.odometry_covariance = (motion @ state.odometry_covariance
                                     @ motion.transpose(0, 2, 1)
                                     + noise @ spread @ noise.transpose(0, 2, 1))
        state.odometry_pose = state.odometry_pose + np.column_stack([step_x, step_y, turn])
        state.odometry_pose[:, 2] = wrap_angle(state.odometry_pose[:, 2])

    def reading(self, index: int) -> OdometryReading:
        state = self.state
        x, y, theta = state.odometry_pose[index].tolist()
        return OdometryReading((x, y, theta), tuple(state.odometry_velocity[index].tolist()),
                               state.odometry_covariance[index].copy(),
                               tuple(state.odometry_variance[index].tolist()))
