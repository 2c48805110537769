"""
What a simulation reports without changing: its entities, poses, velocities, odometry, sensors.

Simulation (simulation.py) makes every change; this base class reads what it keeps, all of it
named in its docstring, so reading and changing are each one module's role. No ROS here.
"""

import math

import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.pose import compose, invert
from stdr_lite.core.entities import NANOSECONDS, RequestError, sensor_groups, SimulatedEntity
from stdr_lite.core.odometry import NO_SPREAD, OdometryReading
from stdr_lite.core.sensors import read_sensors, ReadingPlan


class SimulationReadings:
    """
    The reading half of Simulation, over what it keeps (each set by simulation.py).

    roster (the entities by name and row), bodies (what the last step did to each), world
    (poses, radii, shapes), step_count, dt_ns and settings; and, private to the two halves,
    _terrain (the map's distance fields), _odometry with _odometry_schedule, _sensor_groups,
    _laser_plans and _noise (the sensors' generator).
    """

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
        """Return every entity's name, in the order they were added."""
        return [entity.name for entity in self.roster.entities]

    @property
    def robot_names(self) -> list[str]:
        return [entity.name for entity in self.roster.entities if entity.is_robot]

    @property
    def obstacle_names(self) -> list[str]:
        return [entity.name for entity in self.roster.entities if not entity.is_robot]

    @property
    def obstacles_moving(self) -> bool:
        """Whether any obstacle has a velocity, so its pose changes from step to step."""
        return self.bodies.obstacles_moving

    def __contains__(self, name: str) -> bool:
        return name in self.roster

    def default_name(self, prefix: str = 'robot') -> str:
        """Return <prefix><K> with the smallest K not taken."""
        return self.roster.free_name(prefix)

    def entity(self, name: str) -> SimulatedEntity:
        return self.roster.entities[self.roster.index(name)]

    def robot(self, name: str) -> SimulatedEntity:
        entity = self.entity(name)
        if not entity.is_robot:
            raise RequestError(f'{name} is a {entity.category.value}, not a robot')
        return entity

    def pose(self, name: str) -> tuple[float, float, float]:
        """Return the entity's (x, y, theta) in the map frame."""
        x, y, theta = self.world.poses[self.roster.index(name)].tolist()
        return x, y, theta

    def applied_velocity(self, name: str) -> tuple[float, float, float]:
        """Return the (linear, lateral, angular) velocity of the last step: zero if blocked."""
        index = self.roster.index(name)
        linear, lateral, angular = (float(values[index]) for values in self.bodies.applied)
        return linear, lateral, angular

    def robot_poses(self) -> np.ndarray:
        """Return every robot's (x, y, theta), a row each in robot_names order (a copy)."""
        return self.world.poses[self.roster.robot_rows].copy()

    def robots_stalled(self) -> np.ndarray:
        """Return whether each robot's last step was refused, in robot_names order."""
        return self.bodies.stalled[self.roster.robot_rows].copy()

    def read_lasers(self, names: list[str], spec) -> np.ndarray:
        """
        Read one laser (a LaserSpec) on each robot of names now: a row of ranges each.

        The same readings as read_sensors gives, as one array, for a loop reading the same
        lasers every step (a vector of learning environments).
        """
        key = (tuple(names), spec)
        plan = self._laser_plans.get(key)
        if plan is None:
            plan = self._laser_plans[key] = ReadingPlan(tuple((self.roster.index(name), spec)
                                                              for name in names))
        return plan.read_lasers(self._terrain.finder, self.world.poses, self.world.radii,
                                self.world.shapes, self._noise, self.settings.bodies_meet)

    def sensor_readings(self, name: str) -> dict:
        """Read every sensor of a robot now, whatever their schedule: {frame_id: reading}."""
        specs = [sensor.spec for sensor in self.robot(name).sensors]
        return {spec.frame_id: reading for spec, reading in
                zip(specs, self.read_sensors([(name, spec) for spec in specs]))}

    def stalled(self, name: str) -> bool:
        """Whether the entity's last step was refused: a wall or another body in its way."""
        return bool(self.bodies.stalled[self.roster.index(name)])

    def velocity(self, name: str) -> tuple[float, float, float]:
        """Return the (x, y, angular) velocity of the last step in the map frame."""
        index = self.roster.index(name)
        linear, lateral, angular = self.applied_velocity(name)
        heading = self.bodies.motion[index, 2]
        if math.isnan(heading):
            heading = float(self.world.poses[index, 2])
        cos_heading, sin_heading = math.cos(heading), math.sin(heading)
        return (linear * cos_heading - lateral * sin_heading,
                linear * sin_heading + lateral * cos_heading, angular)

    def odometry_due(self) -> bool:
        """Whether odometry is to be published at this step (every 1/odom_rate_hz of sim time)."""
        return self._odometry_schedule.due(self.time_ns)

    def odometry(self, name: str) -> OdometryReading:
        """
        Return the robot's odometry: its pose in its odom frame and its measured velocity.

        Without noise these are the true pose and the applied velocity, with zero spread.
        """
        if self._odometry.noise.enabled:
            return self._odometry.reading(self.roster.index(name))
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
        if not self._odometry.noise.enabled:
            return 0.0, 0.0, 0.0
        return compose(self.pose(name), invert(self.odometry(name).pose))

    def due_sensors(self, wanted=None) -> list[tuple[str, object]]:
        """
        Return (robot name, sensor spec) for each sensor due at this step of a robot wanted.

        wanted(name) says whether a robot's sensors are of interest (all are by default). Each
        sensor is due once per period of sim time, read or not; sensors of one period and
        phase share a schedule, so a step costs a check per group, not per sensor.
        """
        if self._sensor_groups is None:
            self._sensor_groups = sensor_groups(self.roster.entities, self.time_ns - self.dt_ns)
        due = []
        for schedule, members in self._sensor_groups:
            if schedule.due(self.time_ns):
                due += [(name, spec) for name, specs in members
                        if wanted is None or wanted(name) for spec in specs]
        return due

    def read_sensors(self, jobs: list[tuple[str, object]]) -> list:
        """Read sensors at the current poses: a laser's ranges or a sonar's range, per job."""
        rows = [(self.roster.index(name), spec) for name, spec in jobs]
        return read_sensors(self._terrain.finder, self.world.poses, self.world.radii,
                            self.world.shapes, rows, self._noise, self.settings.bodies_meet)
