"""
A course's ROS domain, which nobody else is in, and the grader's recorder in a Context of it.

With namespaces the domain is the one of the course's own network namespace (SEALED_DOMAIN),
which nothing else can reach; otherwise a domain is claimed by its lock file and kept only if,
after listening a while, it shows no node and no topic of anyone's.
"""

from dataclasses import dataclass
from pathlib import Path
import time

from lab_grader.domains import claim_domain, DomainClaim, NoDomainLeft
from lab_grader.recorder import GradingRecorder
from lab_grader.run_errors import GradingError
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.validation import ConfigError
from waypoint_lab.course import Course

SPIN_PERIOD = 0.05
# A domain is taken only when, after this long listening, it shows no node and no topic.
EMPTY_DOMAIN_WAIT = 0.5
DOMAIN_TRIES = 8
# The one domain of a course in a network namespace of its own: nothing else is there.
SEALED_DOMAIN = 1


@dataclass(frozen=True)
class Recorded:
    """What the recorder leaves once taken down: the statuses, the map, why the bag failed."""

    statuses: tuple = ()
    submitted_map: OccupancyMap | str | None = None
    bag_note: str = ''
    failure: str = ''


class CourseDomain:
    """The domain of one course's run, and the recorder that listens in it."""

    def __init__(self, bag: Path, robot: str, course: Course):
        self._bag, self._robot, self._course = bag, robot, course
        self.claim: DomainClaim | None = None
        self.domain_id: int | None = None
        self.context = self.recorder = self.executor = None
        self.recorded = Recorded()

    def open_sealed(self) -> None:
        """Join the one domain of the course's own network namespace."""
        self._open(SEALED_DOMAIN)

    def take_empty(self) -> None:
        """Claim a domain, and keep it only if nobody is in it; GradingError if none is empty."""
        busy = []
        try:
            for _ in range(DOMAIN_TRIES):
                try:
                    claim = claim_domain(avoid=tuple(held.domain_id for held in busy))
                except NoDomainLeft as error:
                    raise GradingError(str(error)) from None
                self.claim = claim
                self._open(claim.domain_id)
                end = time.monotonic() + EMPTY_DOMAIN_WAIT
                while time.monotonic() < end:
                    self.spin_once()
                others = self.recorder.others()
                if not others:
                    return
                print(f'grade_lab: ROS domain {claim.domain_id} is in use by another program '
                      f'(nodes {", ".join(others[:3])}): taking another', flush=True)
                self.close_recorder()
                rclpy.try_shutdown(context=self.context)
                self.claim = self.context = self.domain_id = None
                busy.append(claim)
        finally:
            for claim in busy:
                claim.release()
        raise GradingError(f'no empty ROS domain: {DOMAIN_TRIES} tried, each in use by another '
                           'program')

    def _open(self, domain_id):
        """Join a domain: the recorder in a Context of it, spun by an executor of its own."""
        context = Context()
        rclpy.init(context=context, domain_id=domain_id,
                   signal_handler_options=SignalHandlerOptions.NO)
        self.context, self.domain_id = context, domain_id
        try:
            self.recorder = GradingRecorder(context, self._bag, self._robot, self._course)
        except ConfigError as error:
            raise GradingError(f'the run cannot be recorded: {error}') from None
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.recorder)

    def spin_once(self) -> None:
        """Let the recorder take what has come, waiting SPIN_PERIOD at most."""
        self.executor.spin_once(timeout_sec=SPIN_PERIOD)

    def close_recorder(self) -> None:
        """Finish the bag and take the recorder down, keeping what it recorded; again: nothing."""
        recorder = self.recorder
        if recorder is None:
            return
        recorder.recording.close()
        self.recorded = Recorded(
            tuple(recorder.statuses), recorder.submitted_map(), recorder.bag_truncated,
            recorder.recording.bag.failure if recorder.recording.failed else '')
        self.executor.remove_node(recorder)
        self.executor.shutdown()
        recorder.destroy_node()
        self.recorder = None

    def close(self) -> None:
        """Take the recorder down, leave the domain and give back its claim; again: nothing."""
        self.close_recorder()
        if self.context is not None:
            rclpy.try_shutdown(context=self.context)
            self.context = None
        if self.claim is not None:
            self.claim.release()
            self.claim = None
