"""
When the simulation steps: paced by a steady timer, held in lockstep, played or paused.

Free-running, a steady-clock timer steps the world every dt / real_time_factor wall seconds
(as fast as it goes for 0). In lockstep, once odometry goes out the next step waits until
every robot's cmd_vel has answered it, so the outcome depends on the commands alone, never on
machine load. Either way nothing steps unless the simulation is playing, or paused with a
step asked for (the SimulateSteps action asks one step at a time).
"""

from collections import deque
import time

from rclpy.clock import Clock, ClockType
from rclpy.task import Future
from simulation_interfaces.msg import SimulationState

# In lockstep, odometry that has gone unanswered this long is published again (same stamp), so
# a controller that started after it was first sent still gets it.
LOCKSTEP_REPEAT_AFTER = 0.5
LATENCY_SAMPLES = 100_000


class Stepper:
    """
    Decides when to call step(), which advances one step and says whether odometry went out.

    In lockstep it alone keeps which robots have not yet answered the latest odometry.

    publish_state() publishes the odometry of the current step again; odometry_subscribers()
    counts who listens to it.
    """

    def __init__(self, node, simulation, step, publish_state, odometry_subscribers,
                 real_time_factor, lockstep):
        self.state = SimulationState.STATE_PLAYING
        self.lockstep = lockstep
        self.answer_latencies = deque(maxlen=LATENCY_SAMPLES)
        self._simulation = simulation
        self._awaited = set()
        self._step, self._publish_state = step, publish_state
        self._odometry_subscribers_now = odometry_subscribers
        self._requests = deque()
        self._published_at = self._repeated_at = 0.0
        self._odometry_subscribers = 0
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        paced = real_time_factor > 0.0
        self._timer = None
        if paced or not lockstep:
            period = simulation.dt / real_time_factor if paced else 0.0
            self._timer = node.create_timer(period, self._on_tick, clock=steady)
        self._step_on_answer = lockstep and not paced
        if lockstep:
            self._repeat = node.create_timer(0.05, self._repeat_unanswered_state, clock=steady)

    @property
    def playing(self) -> bool:
        return self.state == SimulationState.STATE_PLAYING

    def may_step(self) -> bool:
        return self.playing or (self.state == SimulationState.STATE_PAUSED and bool(
            self._requests))

    def set_state(self, state: int) -> None:
        """
        Enter a state; steps asked for while paused fail when leaving pause.

        A paused simulation publishes nothing, so in lockstep the odometry still unanswered is
        published again on play, for the controllers that came while it was paused.
        """
        resumed = state == SimulationState.STATE_PLAYING and not self.playing
        self.state = state
        if state != SimulationState.STATE_PAUSED:
            while self._requests:
                self._requests.popleft().set_result(False)
        if resumed and self.lockstep and self._awaited:
            self._publish_state()
            self._repeated_at = time.monotonic()
        self._wake()

    def request_step(self) -> Future:
        """Ask for one step while paused; the future says True once it is taken."""
        future = Future()
        self._requests.append(future)
        self._wake()
        return future

    def step_now(self) -> None:
        """Take one step at once, whatever the pacing and the answers (StepSimulation)."""
        self._advance()

    def start_over(self, new_time: bool) -> None:
        """
        After a reset or a new world: publish the state there is now.

        In lockstep, a new time (the clock back at 0) awaits every robot's answer to its first
        odometry. A reset that keeps the clock republishes the current stamp, which controllers
        answer once only: the robots that still owe an answer are awaited, as before, and
        those that went with the reset no more.
        """
        self._publish_state()
        if self.lockstep:
            if new_time:
                self.await_answers()
            else:
                self.release()
        self._wake()

    def release(self, everyone: bool = False) -> None:
        """
        Lockstep: stop awaiting the robots that are gone, or everyone when time restarted.

        Odometry from before a restart of time is void: an answer to it steps nothing.
        """
        self._awaited = set() if everyone else self._awaited & set(self._simulation.robot_names)

    def answered(self, name: str) -> None:
        """Lockstep: note a robot's command; step on once every robot has answered."""
        if name in self._awaited:
            self._awaited.discard(name)
            self.answer_latencies.append(time.monotonic() - self._published_at)
            self.step_if_answered()

    def step_if_answered(self) -> None:
        """Unpaced lockstep: run to the next published odometry once all have answered."""
        if self._step_on_answer:
            while self.may_step() and not self._awaited:
                if self._advance():
                    break

    def await_answers(self) -> None:
        """Lockstep: from now on, wait for a command from every robot before stepping."""
        self._awaited = set(self._simulation.robot_names)
        self._published_at = self._repeated_at = time.monotonic()

    def _advance(self):
        published = self._step()
        if published and self.lockstep:
            self.await_answers()
        if not self.playing and self._requests:
            self._requests.popleft().set_result(True)
            self._wake()
        return published

    def _wake(self):
        """Run the timer only while there is stepping to do; kick lockstep when it may go on."""
        if self._timer is not None:
            if self.may_step() and self._timer.is_canceled():
                self._timer.reset()
            elif not self.may_step() and not self._timer.is_canceled():
                self._timer.cancel()
        self.step_if_answered()

    def _on_tick(self):
        if self.may_step() and not self._awaited:
            self._advance()

    def _repeat_unanswered_state(self):
        """Repeat unanswered odometry when a subscriber joins or after a long silence (playing)."""
        subscribers = self._odometry_subscribers_now()
        joined, self._odometry_subscribers = (subscribers > self._odometry_subscribers,
                                              subscribers)
        silent = time.monotonic() - self._repeated_at > LOCKSTEP_REPEAT_AFTER
        if self.playing and self._awaited and (joined or silent):
            self._publish_state()
            self._repeated_at = time.monotonic()
