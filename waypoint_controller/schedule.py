"""When to recompute the command, in odometry stamp time."""


class ControlSchedule:
    """
    Control ticks on a fixed grid of period_ns, driven by odometry stamps.

    A tick falls on the first stamp at or after each grid point, so the mean rate is exactly
    1/period even when the odometry period does not divide the control period (50 Hz odometry,
    20 Hz control: ticks 60, 40, 60, 40 ms apart rather than every 60 ms).
    """

    def __init__(self, period_ns):
        if period_ns <= 0:
            raise ValueError(f'control period must be positive, got {period_ns} ns')
        self.period_ns = period_ns
        self._last = None
        self._next = 0

    def due(self, stamp_ns):
        """Return the nanoseconds since the last tick if stamp_ns is a tick, else None."""
        if self._last is not None and stamp_ns < self._next:
            return None
        elapsed = self.period_ns if self._last is None else stamp_ns - self._last
        self._last = stamp_ns
        self._next = stamp_ns + self.period_ns - (stamp_ns - self._next) % self.period_ns
        return elapsed
