"""
A simulation's entities by name, and what each step leaves on each of them. No ROS here.

The Roster is the one book of entities: their order (a row in every per-entity array, the
World's poses included), their names and which rows are robots. Bodies holds the per-entity
state a step makes and the questions read: the velocity applied, whether the step was refused,
an obstacle's motion. A new per-entity field goes into Bodies (its row added and taken with the
others by Simulation._append and remove), and is read where it is used.
"""

import numpy as np
from stdr_lite.core.entities import RequestError, SimulatedEntity

# An obstacle's motion when it has none: no speed, no turn, no direction of travel.
STILL = (0.0, 0.0, np.nan)


class Roster:
    """Entities in the order they were added, found by name; rows shift down on a removal."""

    def __init__(self):
        self.entities: list[SimulatedEntity] = []
        self._indices: dict[str, int] = {}
        self._robot_rows = None

    def append(self, entity: SimulatedEntity) -> None:
        self.entities.append(entity)
        self._renumber()

    def remove(self, index: int) -> None:
        del self.entities[index]
        self._renumber()

    def index(self, name: str) -> int:
        """Return the row of the entity named name; RequestError if there is none."""
        try:
            return self._indices[name]
        except KeyError:
            raise RequestError(f'no entity named {name!r}') from None

    def __contains__(self, name: str) -> bool:
        return name in self._indices

    @property
    def robot_rows(self) -> np.ndarray:
        """Return the rows of the robots, in order."""
        if self._robot_rows is None:
            self._robot_rows = np.array([index for index, entity in enumerate(self.entities)
                                         if entity.is_robot], dtype=np.int64)
        return self._robot_rows

    def free_name(self, prefix: str) -> str:
        """Return <prefix><K> with the smallest K not taken."""
        return next(f'{prefix}{k}' for k in range(len(self.entities) + 1)
                    if f'{prefix}{k}' not in self._indices)

    def _renumber(self):
        self._indices = {entity.name: index for index, entity in enumerate(self.entities)}
        self._robot_rows = None


class Bodies:
    """
    Per entity, what the last step did and how an obstacle moves: arrays a row per entity.

    applied holds the (linear, lateral, angular) velocities of the last step, zero for a body
    that was blocked; stalled whether its step was refused (a wall or another body in its way);
    motion a moving obstacle's speed, turn rate and direction of travel (NaN: it has none).
    """

    def __init__(self):
        self.applied = (np.zeros(0), np.zeros(0), np.zeros(0))
        self.stalled = np.zeros(0, dtype=bool)
        self.motion = np.empty((0, 3))

    def add_row(self) -> None:
        self.applied = tuple(np.append(values, 0.0) for values in self.applied)
        self.stalled = np.append(self.stalled, False)
        self.motion = np.vstack([self.motion, STILL])

    def remove_row(self, index: int) -> None:
        self.applied = tuple(np.delete(values, index) for values in self.applied)
        self.stalled = np.delete(self.stalled, index)
        self.motion = np.delete(self.motion, index, axis=0)

    def stepped(self, moved: np.ndarray, velocities: tuple) -> None:
        """Note a step: which bodies moved, and the (linear, lateral, angular) each was given."""
        self.stalled = ~moved
        self.applied = tuple(np.where(moved, values, 0.0) for values in velocities)

    @property
    def obstacles_moving(self) -> bool:
        """Whether any body has a motion of its own, so its pose changes from step to step."""
        return bool(np.any(self.motion[:, :2] != 0.0))
