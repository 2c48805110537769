"""A PID controller with output saturation and anti-windup, and the lab's two."""

from waypoint_controller.config import ControllerConfig


class PID:
    """
    PID on an error signal, saturated to +-output_limit.

    Anti-windup by conditional integration: the integral does not grow while the output is
    saturated in the direction of the error, so it never has to unwind after a long turn.
    """

    def __init__(self, kp: float, ki: float = 0.0, kd: float = 0.0,
                 output_limit: float = float('inf')):
        self.retune(kp, ki, kd, output_limit)
        self._integral = 0.0
        self._previous_error = None

    def retune(self, kp: float, ki: float, kd: float, output_limit: float) -> None:
        """Take new gains and limit, keeping the integral and the last error."""
        if min(kp, ki, kd) < 0.0 or output_limit <= 0.0:
            raise ValueError('PID gains must be >= 0 and the output limit positive')
        self.kp, self.ki, self.kd = kp, ki, kd
        self.output_limit = output_limit

    def reset(self) -> None:
        self._integral = 0.0
        self._previous_error = None

    def update(self, error: float, dt: float, kp: float | None = None) -> float:
        """Return the saturated output for this error; kp overrides the proportional gain."""
        kp = self.kp if kp is None else kp
        derivative = 0.0
        if self._previous_error is not None and dt > 0.0:
            derivative = (error - self._previous_error) / dt
        self._previous_error = error
        candidate_integral = self._integral + error * dt
        unsaturated = kp * error + self.ki * candidate_integral + self.kd * derivative
        output = max(-self.output_limit, min(self.output_limit, unsaturated))
        if output == unsaturated or (output > 0.0) != (error > 0.0):
            self._integral = candidate_integral
        return output


def lab_pids(config: ControllerConfig) -> tuple[PID, PID]:
    """Return the lab's two PIDs under config: on heading (to the turn rate), on distance."""
    return (PID(config.heading_kp, config.heading_ki, config.heading_kd, config.max_angular_speed),
            PID(config.distance_kp, config.distance_ki, config.distance_kd,
                config.max_linear_speed))
