"""
When the entities' lasers and sonars fall due, and what they read of the state. No ROS here.

Sensing keeps what reading needs between steps: the sensors' noise generator, the sensors
grouped by reading times, and the reading plans of a loop that reads the same lasers every
step. The groups and plans are worked out from the state's rows and made again whenever its
version moves on (an entity added or removed), so nothing else has to say when they are stale.
"""

from collections.abc import Callable

import numpy as np
from stdr_lite.core.entities import sensor_groups
from stdr_lite.core.robot_description import LaserSpec
from stdr_lite.core.sensors import RangeFinder, read_sensors, ReadingPlan
from stdr_lite.core.state import StateTable


class Sensing:
    """The sensors of the entities of a state, read in its poses by a range finder."""

    def __init__(self, bodies_meet: bool, seed: int):
        self.bodies_meet = bodies_meet
        self.noise = np.random.default_rng(seed)
        self.state, self.finder = StateTable(), None
        self._forget()

    def attach(self, state: StateTable, finder: RangeFinder) -> None:
        """Read the entities of state from now on, in the map of finder."""
        self.state, self.finder = state, finder
        self._forget()

    def restart(self, seed: int, now_ns: int) -> None:
        """Start the noise and every sensor's schedule over, each due a period after now_ns."""
        self.noise = np.random.default_rng(seed)
        for entity in self.state.entities:
            for sensor in entity.sensors:
                sensor.restart(now_ns)
        self._forget()

    def due(self, time_ns: int, dt_ns: int, wanted: Callable[[str], bool] | None = None
            ) -> list[tuple[str, object]]:
        """
        Return (robot name, sensor spec) for each sensor due at time_ns of a robot wanted.

        wanted(name) says whether a robot's sensors are of interest (all are by default). Each
        sensor is due once per period of sim time, read or not; sensors of one period and
        phase share a schedule, so a step costs a check per group, not per sensor.
        """
        if self._groups is None or self._version != self.state.version:
            self._forget()
            self._groups = sensor_groups(self.state.entities, time_ns - dt_ns)
        due = []
        for schedule, members in self._groups:
            if schedule.due(time_ns):
                due += [(name, spec) for name, specs in members
                        if wanted is None or wanted(name) for spec in specs]
        return due

    def read(self, jobs: list[tuple[str, object]]) -> list:
        """Read sensors at the current poses: a laser's ranges or a sonar's range, per job."""
        state = self.state
        rows = [(state.index(name), spec) for name, spec in jobs]
        return read_sensors(self.finder, state.pose, state.radius, state.shapes, rows,
                            self.noise, self.bodies_meet)

    def read_lasers(self, names: list[str], spec: LaserSpec) -> np.ndarray:
        """Read one laser (a LaserSpec) on each robot of names now: a row of ranges each."""
        state = self.state
        if self._version != state.version:
            self._forget()
        key = (tuple(names), spec)
        plan = self._plans.get(key)
        if plan is None:
            plan = self._plans[key] = ReadingPlan(tuple((state.index(name), spec)
                                                        for name in names))
        return plan.read_lasers(self.finder, state.pose, state.radius, state.shapes,
                                self.noise, self.bodies_meet)

    def _forget(self):
        """Drop what was worked out of the rows: they changed, or their schedules did."""
        self._groups, self._plans, self._version = None, {}, self.state.version
