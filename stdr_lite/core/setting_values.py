"""
The values the simulation's settings may take, as plain data: no numpy here.

The simulator node's parameter table (stdr_lite/node/parameters.py) is read before numpy and
numba load, so that a command line is judged in a tenth of a second; it and the core modules
take these from here.
"""

from dataclasses import dataclass

# STDR applies every command as given. A finite bound stays, so that no command can make one
# step's swept path (checked a quarter cell at a time) cost without end: at 100 m/s and 50 Hz
# a step is 2 m, 160 samples of a 5 cm map. The parameters safety_linear_speed and
# safety_angular_speed raise it, up to SAFETY_CEILING (a 200 m step: 16,000 samples).
SAFETY_LINEAR_SPEED = 100.0
SAFETY_ANGULAR_SPEED = 100.0
SAFETY_CEILING = 10_000.0
# Whose described sensor noise is applied: 'auto' reads a file in STDR's layouts (XML, nested
# YAML) as STDR does, which never applies its files' noise, and applies the flat layout's (the
# bundled robots'); 'all' applies every file's; 'none' no file's.
SENSOR_NOISE_MODES = ('auto', 'all', 'none')
# How a pose is advanced over a step: the lab's equation 2, or the exact constant-velocity arc.
EULER = 'euler'
ARC = 'arc'
INTEGRATOR_NAMES = (EULER, ARC)
# Where a robot starts unless told otherwise (the node's initial_pose default too).
DEFAULT_POSE = (1.0, 2.0, 0.0)


@dataclass(frozen=True)
class OdometryNoise:
    """
    The drift coefficients; zero means exact odometry.

    distance: std of the distance error after driving 1 m [m / sqrt(m)]; turn: std of the
    heading error after turning 1 rad [rad / sqrt(rad)]; heading_per_distance: std of the
    heading error after driving 1 m straight [rad / sqrt(m)].
    """

    distance: float = 0.0
    turn: float = 0.0
    heading_per_distance: float = 0.0

    @property
    def enabled(self) -> bool:
        return (self.distance, self.turn, self.heading_per_distance) != (0.0, 0.0, 0.0)
