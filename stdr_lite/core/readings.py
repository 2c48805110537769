"""
What a simulation reports without changing: its entities, poses, velocities, odometry, sensors.

Simulation (simulation.py) makes every change; this base class reads the parts it keeps, each
a public attribute named in its docstring, so reading and changing are each one module's role.
No ROS here.
"""

from collections.abc import Callable
import math

import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.pose import compose, invert
from stdr_lite.core.entities import NANOSECONDS, RequestError, SimulatedEntity
from stdr_lite.core.odometry import NO_SPREAD, OdometryReading
from stdr_lite.core.robot_description import LaserSpec


class SimulationReadings:
    """
    The reading half of Simulation, over the parts it keeps (each set by simulation.py).

    state (every entity's row: pose, footprint, what the last step did, odometry; state.py),
    bodies (the bodies moving in the map: bodies.py), odometer with odometry_schedule
    (odometry.py), sensing (the sensors' schedules, noise and plans: sensing.py), step_count,
    dt_ns and settings.
    """

    @property
    def occupancy_map(self) -> OccupancyMap:
        return self.bodies.map

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
        """Return every entity's name, in the order they were added."""
        return [entity.name for entity in self.state.entities]

    @property
    def robot_names(self) -> list[str]:
        return [entity.name for entity in self.state.entities if entity.is_robot]

    @property
    def obstacle_names(self) -> list[str]:
        return [entity.name for entity in self.state.entities if not entity.is_robot]

    @property
    def obstacles_moving(self) -> bool:
        """Whether any obstacle has a velocity, so its pose changes from step to step."""
        return self.state.obstacles_moving

    def __contains__(self, name: str) -> bool:
        return name in self.state

    def default_name(self, prefix: str = 'robot') -> str:
        """Return <prefix><K> with the smallest K not taken."""
        return self.state.free_name(prefix)

    def entity(self, name: str) -> SimulatedEntity:
        return self.state.entities[self.state.index(name)]

    def robot(self, name: str) -> SimulatedEntity:
        entity = self.entity(name)
        if not entity.is_robot:
            raise RequestError(f'{name} is a {entity.category.value}, not a robot')
        return entity

    def pose(self, name: str) -> tuple[float, float, float]:
        """Return the entity's (x, y, theta) in the map frame."""
        x, y, theta = self.state.pose[self.state.index(name)].tolist()
        return x, y, theta

    def applied_velocity(self, name: str) -> tuple[float, float, float]:
        """Return the (linear, lateral, angular) velocity of the last step: zero if blocked."""
        linear, lateral, angular = self.state.applied[self.state.index(name)].tolist()
        return linear, lateral, angular

    def robot_poses(self) -> np.ndarray:
        """Return every robot's (x, y, theta), a row each in robot_names order (a copy)."""
        return self.state.pose[self.state.robot_rows]

    def robots_stalled(self) -> np.ndarray:
        """Return whether each robot's last step was refused, in robot_names order."""
        return self.state.stalled[self.state.robot_rows]

    def read_lasers(self, names: list[str], spec: LaserSpec) -> np.ndarray:
        """
        Read one laser (a LaserSpec) on each robot of names now: a row of ranges each.

        The same readings as read_sensors gives, as one array, for a loop reading the same
        lasers every step (a vector of learning environments).
        """
        return self.sensing.read_lasers(names, spec)

    def sensor_readings(self, name: str) -> dict:
        """Read every sensor of a robot now, whatever their schedule: {frame_id: reading}."""
        specs = [sensor.spec for sensor in self.robot(name).sensors]
        return {spec.frame_id: reading for spec, reading in
                zip(specs, self.read_sensors([(name, spec) for spec in specs]))}

    def stalled(self, name: str) -> bool:
        """Whether the entity's last step was refused: a wall or another body in its way."""
        return bool(self.state.stalled[self.state.index(name)])

    def velocity(self, name: str) -> tuple[float, float, float]:
        """Return the (x, y, angular) velocity of the last step in the map frame."""
        index = self.state.index(name)
        linear, lateral, angular = self.applied_velocity(name)
        heading = float(self.state.motion[index, 2])
        if math.isnan(heading):
            heading = float(self.state.pose[index, 2])
        cos_heading, sin_heading = math.cos(heading), math.sin(heading)
        return (linear * cos_heading - lateral * sin_heading,
                linear * sin_heading + lateral * cos_heading, angular)

    def odometry_due(self) -> bool:
        """Whether odometry is to be published at this step (every 1/odom_rate_hz of sim time)."""
        return self.odometry_schedule.due(self.time_ns)

    def odometry(self, name: str) -> OdometryReading:
        """
        Return the robot's odometry: its pose in its odom frame and its measured velocity.

        Without noise these are the true pose and the applied velocity, with zero spread.
        """
        if self.odometer.noise.enabled:
            return self.odometer.reading(self.state.index(name))
        return self.ground_truth(name)

    def ground_truth(self, name: str) -> OdometryReading:
        """Return the robot's true pose in the map frame and its applied velocity, exactly."""
        return OdometryReading(self.pose(name), self.applied_velocity(name), NO_SPREAD,
                               (0.0, 0.0, 0.0), exact=True)

    def map_to_odom(self, name: str) -> tuple[float, float, float]:
        """
        Return the transform from the map frame to the robot's odom frame.

        It is what makes map -> odom -> base_link the true pose, as a perfect localiser would
        publish it: the identity while the odometry is exact.
        """
        if not self.odometer.noise.enabled:
            return 0.0, 0.0, 0.0
        return compose(self.pose(name), invert(self.odometry(name).pose))

    def due_sensors(self, wanted: Callable[[str], bool] | None = None
                    ) -> list[tuple[str, object]]:
        """Return (robot name, sensor spec) for each sensor due at this step (Sensing.due)."""
        return self.sensing.due(self.time_ns, self.dt_ns, wanted)

    def read_sensors(self, jobs: list[tuple[str, object]]) -> list:
        """Read sensors at the current poses: a laser's ranges or a sonar's range, per job."""
        return self.sensing.read(jobs)
