"""
One course run in isolation: stdr_lite, a recorder and the submission in a ROS domain of their own.

The simulator starts paused; the recorder (this process, in a Context of the course's domain)
hears its ground truth, then the submission starts and the recorder waits until it matches the
submission's robot_status publisher, so that no status is lost to discovery; only then does
the simulation play. The run ends a little after FINISHED (or ABORTED), after the submission
ends, at the time limit, or when grading is interrupted; everything the run started is then
stopped and the bag closed.
"""

from dataclasses import dataclass
import os
from pathlib import Path
import shutil
import threading
import time
import uuid

from lab_grader.supervision import Supervised
from lab_grader.verdicts import ProcessOutcome
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.logging import LoggingSeverity
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions
from simple_robot_control.bag_recording import BagRecording
from simple_robot_control.domains import claim_domain
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.share import installed_executable, shared_file
from simulation_interfaces.msg import Result, SimulationState
from simulation_interfaces.srv import SetSimulationState
from std_msgs.msg import String
from waypoint_lab.course import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.status import parse_status

PLACEHOLDER = '{waypoints}'
# Everything the run is judged by is kept, however far behind the recorder falls (a lockstep
# simulator runs as fast as the controller answers): nothing is dropped from the queue. Reliable
# readers match the simulator's publishers and the lab's status publisher (rclpy's default,
# reliable and volatile) alike, transient-local ones too.
JUDGED_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
STATUS_HISTORY = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                            durability=DurabilityPolicy.TRANSIENT_LOCAL)
SIMULATOR_START = 60.0
# How long the submission has to make its robot_status publisher before the simulation plays,
# and how long after the recorder has matched it: the publisher's side of the match may come a
# little later, and until then what it sends does not reach the recorder.
STATUS_PUBLISHER_WAIT = 10.0
MATCH_SETTLE = 1.0
# The run goes on this long (wall seconds) after FINISHED or ABORTED, to see the robot stop and
# anything sent after it; and this long after the submission ends by itself.
AFTER_FINISHED = 2.0
AFTER_EXIT = 1.0
# At the end, the recorder has this long to catch up with the simulator; it has when no truth
# came for QUIET seconds.
CATCH_UP = 60.0
QUIET = 0.5
SPIN_PERIOD = 0.05


@dataclass(frozen=True)
class RunSettings:
    """How every course of a grading is run."""

    command: tuple[str, ...]
    cwd: str = '.'
    lockstep: bool = False
    real_time_factor: float = 1.0
    robot_name: str = 'robot0'


@dataclass
class RunResult:
    """What a run left: how the submission ended, its bag, and any failure of the grader's own."""

    outcome: ProcessOutcome
    bag: Path
    error: str = ''


class GradingError(Exception):
    """The grader could not run a course; not the submission's doing."""


def course_environment(domain_id: int) -> dict:
    """Return the environment of a run's processes: loopback discovery in its own domain."""
    environment = dict(os.environ, ROS_DOMAIN_ID=str(domain_id),
                       ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST', ROS_STATIC_PEERS='',
                       PYTHONUNBUFFERED='1')
    environment.setdefault('FASTRTPS_DEFAULT_PROFILES_FILE',
                           shared_file('config', 'fastdds_quick_discovery.xml'))
    return environment


def simulator_command(course, settings) -> list[str]:
    """Return the stdr_lite command line of a course: paused, at the course's start."""
    x, y, theta = course.start
    parameters = {'paused': 'true', 'lockstep': str(settings.lockstep).lower(),
                  'real_time_factor': f'{settings.real_time_factor:.6f}',
                  'initial_pose': f'[{x!r}, {y!r}, {theta!r}]',
                  'robot_name': settings.robot_name}
    if course.map_file:
        parameters['map_yaml'] = course.map_file
    if course.robot_file:
        parameters['robot_description'] = course.robot_file
    arguments = [item for name, value in parameters.items()
                 for item in ('-p', f'{name}:={value}')]
    return [installed_executable('stdr_lite'), '--ros-args', *arguments]


class GradingRecorder(GuardedNode):
    """Records the run's topics into its bag, follows robot_status, and plays the simulation."""

    def __init__(self, context, bag, robot_name, course_name):
        # Each course's recorder is a node of this process: one rosout publisher per name.
        super().__init__('grade_lab_recorder', context=context, enable_rosout=False)
        self.get_logger().set_level(LoggingSeverity.WARN)
        robot = f'/{robot_name}'
        self.recording = BagRecording(self, bag, (f'/{COURSE_TOPIC}', '/map'), send_times=True,
                                      course=course_name)
        self.simulator_topics = {f'{robot}/ground_truth': 'nav_msgs/msg/Odometry',
                                 f'{robot}/stall': 'std_msgs/msg/Bool'}
        self.truth_sent = self.truth_heard_at = 0
        for topic, type_name in self.simulator_topics.items():
            self.recording.record_now(topic, type_name, JUDGED_QOS,
                                      self._on_truth if 'ground_truth' in topic else None)
        self.ended_at = None
        # A transient-local status publisher (the lab's controller's) replays to the second
        # subscription what the first missed while the publisher's side of the match lagged.
        self.recording.record_now(f'/{STATUS_TOPIC}', 'std_msgs/msg/String', JUDGED_QOS,
                                  self._on_status, STATUS_HISTORY)
        self._set_state = self.create_client(SetSimulationState,
                                             '/stdr_lite/set_simulation_state')

    @property
    def simulator_matched(self) -> bool:
        """Whether the simulator's topics the run is judged by have their publisher matched."""
        return all(self.recording.subscription(topic).get_publisher_count()
                   for topic in self.simulator_topics)

    @property
    def status_publishers(self) -> int:
        return self.recording.subscription(f'/{STATUS_TOPIC}').get_publisher_count()

    def _on_truth(self, _, sent):
        self.truth_sent, self.truth_heard_at = sent, time.monotonic()

    def _on_status(self, data, _):
        status = parse_status(deserialize_message(data, String).data)
        if status is not None and status.ends_run and self.ended_at is None:
            self.ended_at = time.monotonic()

    def play(self, spin):
        """Ask the simulator to play; GradingError if it does not."""
        if not spin(self._set_state.service_is_ready, SIMULATOR_START):
            raise GradingError('the simulator offers no set_simulation_state service')
        future = self._set_state.call_async(SetSimulationState.Request(
            state=SimulationState(state=SimulationState.STATE_PLAYING)))
        if not spin(future.done, SIMULATOR_START) or future.result().result.result != (
                Result.RESULT_OK):
            raise GradingError('the simulator did not start playing')


def run_course(course, settings, folder, stopping: threading.Event) -> RunResult:
    """Run one course for the submission in folder (made if need be) and return its result."""
    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    waypoints = folder / 'waypoints.txt'
    shutil.copyfile(course.waypoint_file, waypoints)
    command = [part.replace(PLACEHOLDER, str(waypoints)) for part in settings.command]
    claim = claim_domain()
    environment = course_environment(claim.domain_id)
    marker = uuid.uuid4().hex
    bag = folder / 'run.mcap'
    simulator = Supervised(simulator_command(course, settings), f'{marker}:simulator',
                           folder / 'simulator.log', env=environment)
    context = Context()
    rclpy.init(context=context, domain_id=claim.domain_id,
               signal_handler_options=SignalHandlerOptions.NO)
    run = _Run(course, context, stopping, simulator)
    try:
        return run.go(bag, settings, command, environment, f'{marker}:submission')
    finally:
        run.close()
        simulator.stop()
        rclpy.try_shutdown(context=context)
        claim.release()


class _Run:
    """The course's run, step by step, in the course's own Context."""

    def __init__(self, course, context, stopping, simulator):
        self.course, self.context, self.stopping = course, context, stopping
        self.simulator = simulator
        self.recorder = self.executor = self.submission = None

    def spin(self, condition, timeout):
        """Spin until condition() holds; False after timeout, or if grading stops first."""
        deadline = time.monotonic() + timeout
        while not condition():
            if self.stopping.is_set() or time.monotonic() > deadline:
                return False
            if not self.simulator.running:
                raise GradingError(f'the simulator ended (exit code {self.simulator.exit_code}'
                                   f'): {" | ".join(self.simulator.last_lines)[-300:]}')
            self.executor.spin_once(timeout_sec=SPIN_PERIOD)
        return True

    def go(self, bag, settings, command, environment, marker):
        try:
            self.recorder = GradingRecorder(self.context, bag, settings.robot_name,
                                            self.course.waypoint_file.name)
            self.executor = SingleThreadedExecutor(context=self.context)
            self.executor.add_node(self.recorder)
            if not self.spin(lambda: self.recorder.simulator_matched, SIMULATOR_START):
                raise GradingError("the simulator's ground truth and stall topics did not "
                                   f'show within {SIMULATOR_START:g} s')
            self.submission = Supervised(command, marker, bag.parent / 'output.txt',
                                         cwd=settings.cwd, env=environment)
            if self.spin(lambda: self.recorder.status_publishers or not self.submission.running,
                         STATUS_PUBLISHER_WAIT):
                self.spin(lambda: False, MATCH_SETTLE)
            self.recorder.play(self.spin)
            timed_out = self._until_over()
            self._catch_up()
            if self.recorder.recording.failed:
                raise GradingError('the run could not be recorded: '
                                   f'{self.recorder.recording.bag.failure}')
        except GradingError as error:
            return RunResult(self._stop_submission(), bag, str(error))
        if self.stopping.is_set():
            return RunResult(self._stop_submission(), bag, 'grading was interrupted')
        return RunResult(self._stop_submission(timed_out), bag)

    def _until_over(self):
        """Spin until the run is over; return whether the time limit ended it."""
        deadline = time.monotonic() + self.course.time_limit

        def over():
            now = time.monotonic()
            ended = self.recorder.ended_at
            if ended is not None:
                return now - ended >= AFTER_FINISHED
            return not self.submission.running and now - self.submission.ended_at >= AFTER_EXIT
        self.spin(over, self.course.time_limit)
        return not over() and time.monotonic() >= deadline

    def _catch_up(self):
        """
        Record what the simulator had sent when the run was over, however far behind.

        The recorder may lag the simulator (a lockstep run as fast as the controller goes): the
        run is recorded until it has the true pose sent at the moment the run was over, or
        until the simulator has sent nothing for a while (in lockstep it waits for a controller
        that has ended).
        """
        over = time.time_ns()

        def caught_up():
            return (self.recorder.truth_sent >= over
                    or time.monotonic() - self.recorder.truth_heard_at > QUIET)
        if not self.spin(caught_up, CATCH_UP) and not self.stopping.is_set():
            raise GradingError(f'the recorder was still {CATCH_UP:g} s behind the simulator at '
                               'the end (the machine is too busy): grade with fewer --jobs or '
                               'a lower --real-time-factor')

    def _stop_submission(self, timed_out=False):
        """Close the bag (the run is what it recorded), then stop the submission."""
        self.close()
        if self.submission is None:
            return ProcessOutcome(start_error='not started: the grader failed first')
        if self.submission.start_error:
            return ProcessOutcome(start_error=self.submission.start_error)
        seconds = self.submission.seconds
        ended_by, stop_seconds, leftovers = self.submission.stop()
        return ProcessOutcome(ended_by=ended_by, exit_code=self.submission.exit_code,
                              seconds=seconds, stop_seconds=stop_seconds, timed_out=timed_out,
                              last_lines=tuple(self.submission.last_lines),
                              leftovers=tuple(leftovers))

    def close(self):
        """Finish the bag and take the recorder down; again is harmless."""
        if self.recorder is not None:
            self.recorder.recording.close()
            self.executor.remove_node(self.recorder)
            self.executor.shutdown()
            self.recorder.destroy_node()
            self.recorder = None
