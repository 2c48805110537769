"""
One course run in isolation: stdr_lite, a recorder and the submission in a ROS domain of their own.

With namespaces (sandbox.py) the domain is in a network namespace of the course's own, which
nothing else can reach; otherwise the grader first claims a domain and checks that it is empty
(no node, no topic of anyone's). The simulator
starts supervised (stdr_lite's supervisor_fd): paused, serving nothing that changes the world,
its true state sent to the grader over a socket no other process holds. The recorder (this
process, in a Context of the course's domain) records the run's bag and keeps every robot_status
message with its send time; then the submission starts, and once its status publisher is
matched the simulation plays. While the run goes, whoever else publishes on the simulator's
topics is named (publishers.py): the submission's doing is a foul (the course fails), and
another program in the domain an error. The run ends a little after FINISHED (or ABORTED),
after the submission ends, at the time limit, on a foul, or when grading is interrupted;
everything the run started is then stopped and the bag closed. The judge's evidence is the
socket's truth and the statuses kept here, never a file the submission could reach.
"""

from contextlib import nullcontext
import os
from pathlib import Path
import shutil
import tempfile
import threading
import time
import uuid

from lab_grader.domains import claim_domain, NoDomainLeft
from lab_grader.grading import RunEvidence
from lab_grader.jail import SANDBOX_HOME
from lab_grader.publishers import find_intruders, socket_owners, strangers
from lab_grader.recorder import GradingRecorder
from lab_grader.run_environment import (course_environment, PLACEHOLDER, RunSettings,
                                        simulator_command, submission_environment)
from lab_grader.sandbox import NAMESPACES, network_of_its_own
from lab_grader.simulator_link import SimulatorLink
from lab_grader.submission_process import Submission
from lab_grader.supervision import Supervised
from lab_grader.verdicts import ProcessOutcome
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions
from simple_robot_control.validation import ConfigError
from waypoint_lab.course import Course

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
# came for QUIET seconds, and no status either (a flood still queued is counted).
CATCH_UP = 60.0
QUIET = 0.5
SPIN_PERIOD = 0.05
# A domain is taken only when, after this long listening, it shows no node and no topic.
EMPTY_DOMAIN_WAIT = 0.5
DOMAIN_TRIES = 8
# How often the graph is read for intruders, and the domain's sockets and the submission's
# working folder looked at (wall seconds).
WATCH_PERIOD = 0.1
SOCKETS_PERIOD = 1.0
# The one domain of a course in a network namespace of its own: nothing else is there.
SEALED_DOMAIN = 1


class GradingError(Exception):
    """The grader could not run a course; not the submission's doing."""


class Foul(Exception):
    """The submission did what ends a run at once and fails the course (the message says what)."""


def run_course(course: Course, settings: RunSettings, folder: Path,
               stopping: threading.Event) -> RunEvidence:
    """Run one course for the submission in folder (made if need be) and return its result."""
    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    sandbox = settings.sandbox
    with network_of_its_own() if sandbox.mode == NAMESPACES else nullcontext():
        run = _Run(course, stopping, folder, sandbox)
        try:
            return run.go(settings)
        finally:
            run.close()


class _Run:
    """The course's run, step by step, in a Context of the course's own domain."""

    def __init__(self, course, stopping, folder, sandbox):
        self.course, self.stopping, self.folder = course, stopping, folder
        self.sandbox = sandbox
        self.bag = folder / 'run.mcap'
        # The grader's own files of the run, and the submission's working folder: its home,
        # with its copy of the waypoint file; both go at the end. Sealed, the submission runs
        # as a uid of its own (and with namespaces its home is its own /tmp's).
        self.private = Path(tempfile.mkdtemp(prefix='grade_lab-'))
        self.working = Path(tempfile.mkdtemp(prefix='grade_lab-work-'))
        shutil.copyfile(course.waypoint_file, self.working / 'waypoints.txt')
        self.uid = sandbox.uids.take() if sandbox.sealed else None
        self.home = SANDBOX_HOME if sandbox.mode == NAMESPACES else str(self.working)
        self.simulator_gids = set()
        self._sockets_at = 0.0
        self.claim = self.context = self.simulator = self.link = None
        self.recorder = self.executor = self.submission = None
        self.fouls, self.strangers = [], []
        # What the recorder leaves once taken down: the statuses, and why the bag failed if so.
        self.recorder_statuses, self.recorder_failure, self.bag_note = [], '', ''
        self.recorder_map = None
        self._last_heard = (time.monotonic(), 0)
        self._watched_at = 0.0

    def spin(self, condition, timeout):
        """Spin until condition() holds; False after timeout, or if grading stops first."""
        deadline = time.monotonic() + timeout
        while not condition():
            if self.stopping.is_set() or time.monotonic() > deadline:
                return False
            self._check_simulator()
            self._watch()
            self.executor.spin_once(timeout_sec=SPIN_PERIOD)
        return True

    def _check_simulator(self):
        simulator = self.simulator
        if simulator is None or simulator.running:
            return
        code = simulator.exit_code
        if code is not None and code <= 0 and self.submission is not None:
            raise Foul(f'the simulator was ended during the run ({_ended_text(code)}), not by '
                       'the grader')
        raise GradingError(f'the simulator ended (exit code {code}): '
                           f'{" | ".join(simulator.last_lines)[-300:]}')

    def _watch(self):
        """Name whoever publishes where only the simulator, or the submission, may."""
        if self.submission is None or time.monotonic() - self._watched_at < WATCH_PERIOD:
            return
        self._watched_at = time.monotonic()
        recorder = self.recorder
        outsiders = []
        if self.sandbox.mode != NAMESPACES and (
                time.monotonic() - self._sockets_at >= SOCKETS_PERIOD):
            self._sockets_at = time.monotonic()
            run_pids = {os.getpid(), self.simulator.pid} | self.submission.pids()
            outsiders = strangers(socket_owners(self.claim.domain_id), run_pids, self.uid)
        found = find_intruders(recorder.publishers(recorder.watched), self.simulator_gids,
                               outsiders)
        self.fouls += [line for line in found.fouls if line not in self.fouls]
        self.strangers += [line for line in found.strangers if line not in self.strangers]
        self._check_flood()
        if self.fouls:
            raise Foul(self.fouls[0])
        if self.strangers:
            raise GradingError(f"{self.strangers[0]}: not the submission's doing; grade again")

    def _check_flood(self):
        """Raise Foul once the submission has sent more statuses than any honest run."""
        recorder = self.recorder
        if recorder.flooded:
            self.fouls.append(f'sent {recorder.sent_statuses} messages on robot_status, more '
                              f'than {recorder.status_limit} (an honest run sends '
                              f'{len(self.course.waypoints) + 2}): the run was ended there')
            raise Foul(self.fouls[0])

    def _open_domain(self, domain_id):
        """Join a domain: the recorder in a Context of it, spun by an executor of its own."""
        context = Context()
        rclpy.init(context=context, domain_id=domain_id,
                   signal_handler_options=SignalHandlerOptions.NO)
        self.context = context
        try:
            self.recorder = GradingRecorder(context, self.bag, self.course_robot, self.course)
        except ConfigError as error:
            raise GradingError(f'the run cannot be recorded: {error}') from None
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.recorder)

    def _take_empty_domain(self):
        """Claim a domain, and keep it only if nobody is in it; GradingError if none is empty."""
        busy = []
        try:
            for _ in range(DOMAIN_TRIES):
                try:
                    claim = claim_domain(avoid=tuple(held.domain_id for held in busy))
                except NoDomainLeft as error:
                    raise GradingError(str(error)) from None
                self.claim = claim
                self._open_domain(claim.domain_id)
                end = time.monotonic() + EMPTY_DOMAIN_WAIT
                while time.monotonic() < end:
                    self.executor.spin_once(timeout_sec=SPIN_PERIOD)
                others = self.recorder.others()
                if not others:
                    return
                print(f'grade_lab: ROS domain {claim.domain_id} is in use by another program '
                      f'(nodes {", ".join(others[:3])}): taking another', flush=True)
                self._close_recorder()
                rclpy.try_shutdown(context=self.context)
                self.claim = self.context = None
                busy.append(claim)
        finally:
            for claim in busy:
                claim.release()
        raise GradingError(f'no empty ROS domain: {DOMAIN_TRIES} tried, each in use by another '
                           'program')

    def go(self, settings: RunSettings) -> RunEvidence:
        """Run the course: its domain, the simulator, the submission, the run to its end."""
        self.course_robot = settings.robot_name
        try:
            if self.sandbox.mode == NAMESPACES:
                self._open_domain(SEALED_DOMAIN)
                domain_id = SEALED_DOMAIN
            else:
                self._take_empty_domain()
                domain_id = self.claim.domain_id
            environment = course_environment(domain_id, self.sandbox.sealed)
            marker = uuid.uuid4().hex
            self._start_simulator(settings, environment, marker)
            self._start_submission(settings, environment, marker)
            if not self.link.play():
                raise GradingError('the simulator did not start playing')
            timed_out = self._until_over()
            self._catch_up()
            self._check_flood()
        except Foul as foul:
            if str(foul) not in self.fouls:
                self.fouls.append(str(foul))
            return self._result(self._stop_submission())
        except GradingError as error:
            return self._result(self._stop_submission(), str(error))
        if self.stopping.is_set():
            return self._result(self._stop_submission(), 'grading was interrupted')
        outcome = self._stop_submission(timed_out)
        if self.recorder_failure:
            return self._result(outcome, f'the run could not be recorded: {self.recorder_failure}')
        return self._result(outcome)

    def _start_simulator(self, settings, environment, marker):
        """Start the simulator, supervised, and wait until its truth and topics show."""
        self.link = SimulatorLink(settings.robot_name)
        self.simulator = Supervised(
            simulator_command(self.course, settings, self.link.descriptor, self.private),
            f'{marker}:simulator', self.folder / 'simulator.log', env=environment,
            pass_fds=(self.link.descriptor,))
        self.link.handed_over()
        if not self.spin(lambda: self.link.limits is not None
                         and self.recorder.simulator_matched, SIMULATOR_START):
            raise GradingError("the simulator's ground truth and stall topics did not "
                               f'show within {SIMULATOR_START:g} s')
        # Read by now: the file names the course's world, so it goes before the submission.
        shutil.rmtree(self.private, ignore_errors=True)
        # The domain held the simulator and the grader alone: these endpoints are its.
        self.simulator_gids = {publisher.gid for publisher
                               in self.recorder.publishers(self.recorder.watched)}

    def _start_submission(self, settings, environment, marker):
        """Start the submission (jailed where it has a uid) and give it time to publish."""
        waypoints = f'{self.home}/waypoints.txt'
        command = [part.replace(PLACEHOLDER, waypoints) for part in settings.command]
        jail = None if self.uid is None else self.sandbox.jail(
            self.uid, settings.cwd, {'waypoints.txt': str(self.working / 'waypoints.txt')})
        self.submission = Submission(
            command, f'{marker}:submission', self.folder / 'output.txt', cwd=settings.cwd,
            env=submission_environment(environment, self.home, settings.hidden),
            memory_mb=settings.memory_mb, jail=jail)
        if self.spin(lambda: self.recorder.status_publishers or not self.submission.running,
                     STATUS_PUBLISHER_WAIT):
            self.spin(lambda: False, MATCH_SETTLE)

    def _result(self, outcome, error=''):
        """Return the run's evidence: the truth the simulator sent up to now, the statuses."""
        self.close()
        link = self.link
        return RunEvidence(outcome, self.bag, error, link.truth() if link else [],
                           list(self.recorder_statuses), link.limits if link else None,
                           tuple(self.fouls), self.recorder_map,
                           (self.bag_note,) if self.bag_note else ())

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
        Take in what had been sent when the run was over, however far behind.

        The simulator's socket is read as fast as it comes; the recorder's ROS messages (the
        statuses among them) may lag (a lockstep run goes as fast as the controller): it has
        caught up once it has the ROS truth sent at the moment the run was over, or when
        nothing has come for a while (in lockstep the simulator waits for a controller that
        has ended). Statuses waiting in the recorder's subscription are taken at each look:
        a busy executor took a flood's too slowly to count them before they fell quiet.
        """
        over = time.time_ns()
        recorder = self.recorder

        def caught_up():
            taken = recorder.take_waiting_statuses()
            now = time.monotonic()
            return (self.link.last_sent >= over or self._quiet(self.link.last_sent)) and (
                recorder.truth_sent >= over or now - recorder.truth_heard_at > QUIET) and (
                not taken and now - recorder.status_heard_at > QUIET)
        if not self.spin(caught_up, CATCH_UP) and not self.stopping.is_set():
            raise GradingError(f'the recorder was still {CATCH_UP:g} s behind the simulator at '
                               'the end (the machine is too busy): grade with fewer --jobs or '
                               'a lower --real-time-factor')

    def _quiet(self, sent):
        """Whether the simulator's socket has said nothing new for QUIET seconds."""
        if sent != self._last_heard[1]:
            self._last_heard = (time.monotonic(), sent)
        return time.monotonic() - self._last_heard[0] > QUIET

    def _stop_submission(self, timed_out=False):
        """Close the bag (the run is what it recorded), then stop the submission."""
        self._close_recorder()
        if self.submission is None:
            return ProcessOutcome(start_error='not started: the grader failed first')
        if self.submission.start_error:
            return ProcessOutcome(start_error=self.submission.start_error)
        seconds = self.submission.seconds
        if self.submission.disk_full():
            self.fouls.append(f'filled its working space: the {self.sandbox.disk_mb} MB of /tmp '
                              '(with /dev/shm and /var/tmp) it may write (grade_lab --disk)')
        ended_by, stop_seconds, leftovers = self.submission.stop()
        return ProcessOutcome(ended_by=ended_by, exit_code=self.submission.exit_code,
                              seconds=seconds, stop_seconds=stop_seconds, timed_out=timed_out,
                              last_lines=tuple(self.submission.last_lines),
                              leftovers=tuple(leftovers))

    def _close_recorder(self):
        """Finish the bag and take the recorder down, keeping its statuses; again is harmless."""
        if self.recorder is not None:
            self.recorder.recording.close()
            self.recorder_statuses = list(self.recorder.statuses)
            self.recorder_map = self.recorder.submitted_map()
            self.bag_note = self.recorder.bag_truncated
            self.recorder_failure = self.recorder.recording.bag.failure \
                if self.recorder.recording.failed else ''
            self.executor.remove_node(self.recorder)
            self.executor.shutdown()
            self.recorder.destroy_node()
            self.recorder = None

    def close(self):
        """Stop whatever of the run still goes (the submission before); again is harmless."""
        self._close_recorder()
        if self.submission is not None and self.submission.running:
            self._stop_submission()
        if self.link is not None:
            self.link.close()
        if self.simulator is not None:
            self.simulator.stop()
        if self.context is not None:
            rclpy.try_shutdown(context=self.context)
            self.context = None
        if self.claim is not None:
            self.claim.release()
            self.claim = None
        shutil.rmtree(self.private, ignore_errors=True)
        shutil.rmtree(self.working, ignore_errors=True)
        if self.uid is not None:
            self.sandbox.uids.give_back(self.uid)
            self.uid = None


def _ended_text(code):
    return 'exit code 0 after a signal' if code == 0 else f'killed by signal {-code}'
