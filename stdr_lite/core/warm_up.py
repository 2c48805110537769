"""
Compile the core's numba functions into their cache once, at install, not in a user's run.

numba compiles a function on its first call (seconds each, 15 s for the core) and caches the
machine code beside its module; a later process loads it in milliseconds. `make install` runs
this from outside the tree (the installed copy's cache), `make test` from the tree (the cache of
the copy the in-process tests import): otherwise the first run to step, collide or read a laser
would stand still meanwhile, and two test workers would compile the same code side by side.
"""

import numpy as np
from stdr_lite.core.entities import SimulationSettings
from stdr_lite.core.loading import load_world
from stdr_lite.core.setting_values import ARC, EULER, OdometryNoise
from stdr_lite.core.simulation import FEW_ROBOTS


def compile_core() -> None:
    """Step a small crowd into walls and each other, both integrators, odometry drifting."""
    count = FEW_ROBOTS + 1
    drift = OdometryNoise(0.05, 0.05, 0.01)
    for integrator in (EULER, ARC):
        simulation = load_world(robots=[(f'robot{index}', (1.0 + 0.45 * index, 1.0, 0.0))
                                        for index in range(count)],
                                settings=SimulationSettings(integrator=integrator,
                                                            odometry_noise=drift))
        for _ in range(5):
            simulation.command_robots(np.full(count, 9.0), np.linspace(-1.0, 1.0, count))
            simulation.step()
        simulation.command('robot0', -0.5, 0.0)
        simulation.step()
        simulation.sensor_readings('robot0')
