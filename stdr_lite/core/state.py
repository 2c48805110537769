"""
Every entity of a simulation in one store: a row each, a column per quantity. No ROS here.

The columns are numpy arrays, structure-of-arrays, so a step works on all entities at once:
the Bodies move the poses (bodies.py), the held commands drive the robots (commands.py), the
odometry measures what they did (odometry.py), the sensors read the poses (sensing.py); each
reads and writes its columns here and keeps no rows of its own. Adding or removing an entity is
one call (append, remove) that changes every column and the roster of names at once, and moves
on the version by which caches of the rows know they are out of date.
"""

from collections.abc import Iterable

import numpy as np
from stdr_lite.core.entities import RequestError, SimulatedEntity

# An obstacle's motion when it has none: no speed, no turn, no direction of travel.
STILL = (0.0, 0.0, np.nan)
# The columns, each with the shape of one row and its type.
COLUMNS = {
    'pose': ((3,), float),              # x, y, theta in the map frame
    'radius': ((), float),              # the footprint's circle (a polygon's circumradius)
    'polygonal': ((), bool),            # whether the footprint is a polygon (shapes holds it)
    'robot': ((), bool),                # a robot (driven by commands) or an obstacle
    'command': ((3,), float),           # linear, lateral, angular held since commanded_at
    'commanded_at': ((), float),        # sim seconds
    'applied': ((3,), float),           # linear, lateral, angular of the last step (0: blocked)
    'stalled': ((), bool),              # whether the last step was refused
    'motion': ((3,), float),            # an obstacle's speed, turn rate, heading of travel
    'odometry_pose': ((3,), float),     # the pose the odometry measures, in its odom frame
    'odometry_velocity': ((3,), float),
    'odometry_variance': ((3,), float),
    'odometry_covariance': ((3, 3), float),
}


class StateTable:
    """
    The entities' state, a row per entity in the order they were added.

    entities holds each row's SimulatedEntity (None for a bare body, as the Bodies' tests
    place), shapes each polygon's corners (None for a circle); the other columns are arrays
    named in COLUMNS. A removal moves the rows after it down one.
    """

    def __init__(self):
        self.entities: list[SimulatedEntity | None] = []
        self.shapes: list[tuple | None] = []
        for name, (shape, kind) in COLUMNS.items():
            setattr(self, name, np.zeros((0, *shape), dtype=kind))
        self.version = 0
        self._rows: dict[str, int] = {}
        self._robot_rows = np.zeros(0, dtype=np.int64)

    @classmethod
    def of_bodies(cls, poses: Iterable[tuple], radius: float = 0.0) -> 'StateTable':
        """Return a state of bare circular bodies at poses: for a part of the core used alone."""
        state = cls()
        for pose in poses:
            state.append(pose, radius)
        return state

    def __len__(self) -> int:
        return len(self.entities)

    def append(self, pose: tuple, radius: float, shape: tuple | None = None,
               entity: SimulatedEntity | None = None) -> int:
        """Add a row standing still at pose, with odometry starting there; return its row."""
        pose = np.asarray(pose, dtype=float)
        row = {'pose': pose, 'radius': radius, 'polygonal': shape is not None,
               'robot': entity is not None and entity.is_robot, 'motion': STILL,
               'odometry_pose': pose}
        for name, (row_shape, kind) in COLUMNS.items():
            value = np.broadcast_to(np.asarray(row.get(name, 0), dtype=kind), row_shape)
            setattr(self, name, np.concatenate([getattr(self, name), value[None]]))
        self.entities.append(entity)
        self.shapes.append(shape)
        self._renumber()
        return len(self) - 1

    def remove(self, index: int) -> None:
        """Take row index out of every column."""
        for name in COLUMNS:
            setattr(self, name, np.delete(getattr(self, name), index, axis=0))
        del self.entities[index]
        del self.shapes[index]
        self._renumber()

    def index(self, name: str) -> int:
        """Return the row of the entity named name; RequestError if there is none."""
        try:
            return self._rows[name]
        except KeyError:
            raise RequestError(f'no entity named {name!r}') from None

    def __contains__(self, name: str) -> bool:
        return name in self._rows

    def name_of(self, index: int) -> str:
        """Return the name of row index: its entity's, or 'body <index>' for a bare body."""
        entity = self.entities[index]
        return f'body {index}' if entity is None else entity.name

    @property
    def robot_rows(self) -> np.ndarray:
        """Return the rows of the robots, in order."""
        return self._robot_rows

    def free_name(self, prefix: str) -> str:
        """Return <prefix><K> with the smallest K not taken."""
        return next(f'{prefix}{k}' for k in range(len(self) + 1)
                    if f'{prefix}{k}' not in self._rows)

    def stepped(self, moved: np.ndarray, velocities: np.ndarray) -> None:
        """Note a step: which bodies moved, and the (linear, lateral, angular) rows given."""
        self.stalled = ~moved
        self.applied = np.where(moved[:, None], velocities, 0.0)

    @property
    def obstacles_moving(self) -> bool:
        """Whether any body has a motion of its own, so its pose changes from step to step."""
        return bool(np.any(self.motion[:, :2] != 0.0))

    def _renumber(self):
        self._rows = {entity.name: index for index, entity in enumerate(self.entities)
                      if entity is not None}
        self._robot_rows = np.flatnonzero(self.robot).astype(np.int64)
        self.version += 1
