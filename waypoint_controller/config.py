"""The reference controller's limits, goal set and gains: plain data, light to load."""

from dataclasses import dataclass

from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED,
                                MAX_LINEAR_SPEED)


@dataclass(frozen=True)
class ControllerConfig:
    """Limits, goal set and gains; SI units and radians."""

    max_linear_speed: float = MAX_LINEAR_SPEED
    max_angular_speed: float = MAX_ANGULAR_SPEED
    distance_tolerance: float = DISTANCE_TOLERANCE
    angle_tolerance: float = ANGLE_TOLERANCE
    heading_kp: float = 4.0
    heading_ki: float = 0.5
    heading_kd: float = 0.0
    distance_kp: float = 5.0
    distance_ki: float = 0.0
    distance_kd: float = 0.0

    def validate(self) -> None:
        """Raise ValueError naming the first field out of range."""
        for name in ('max_linear_speed', 'max_angular_speed', 'distance_tolerance',
                     'angle_tolerance', 'heading_kp', 'distance_kp'):
            if not getattr(self, name) > 0.0:
                raise ValueError(f'{name} must be positive, got {getattr(self, name)}')
        for name in ('heading_ki', 'heading_kd', 'distance_ki', 'distance_kd'):
            if not getattr(self, name) >= 0.0:
                raise ValueError(f'{name} must be >= 0, got {getattr(self, name)}')
