"""
One course run in isolation: stdr_lite, a recorder and the submission in a ROS domain of their own.

The run's sequence is here; its domain and recorder are course_domain.py's, what ends it early
run_watch.py's. With namespaces (sandbox.py) the domain is in a network namespace of the
course's own, which nothing else can reach; otherwise the grader first claims a domain and
checks that it is empty (no node, no topic of anyone's). The simulator starts supervised
(stdr_lite's supervisor_fd): paused, serving nothing that changes the world, its true state sent
to the grader over a socket no other process holds. The recorder (this process, in a Context of
the course's domain) records the run's bag and keeps every robot_status message with its send
time; then the submission starts, and once its status publisher is matched the simulation plays.
While the run goes, whoever else publishes on the simulator's topics is named: the submission's
doing is a foul (the course fails), another program in the domain an error. The run ends a
little after FINISHED (or ABORTED), after the submission ends, at the time limit, on a foul, or
when grading is interrupted; everything the run started is then stopped and the bag closed. The
judge's evidence is the socket's truth and the statuses kept here, never a file the submission
could reach.
"""

from contextlib import nullcontext
from pathlib import Path
import shutil
import tempfile
import threading
import time
import uuid

from lab_grader.course_domain import CourseDomain
from lab_grader.grading import RunEvidence
from lab_grader.jail import SANDBOX_HOME
from lab_grader.run_environment import (course_environment, PLACEHOLDER, RunSettings,
                                        simulator_command, submission_environment)
from lab_grader.run_errors import Foul, GradingError
from lab_grader.run_watch import RunWatch
from lab_grader.sandbox import NAMESPACES, network_of_its_own
from lab_grader.simulator_link import SimulatorLink
from lab_grader.submission_process import Submission
from lab_grader.supervision import Supervised
from lab_grader.verdicts import ProcessOutcome
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


def run_course(course: Course, settings: RunSettings, folder: Path,
               stopping: threading.Event) -> RunEvidence:
    """Run one course for the submission in folder (made if need be) and return its result."""
    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    sandbox = settings.sandbox
    with network_of_its_own() if sandbox.mode == NAMESPACES else nullcontext():
        run = _Run(course, settings.robot_name, stopping, folder, sandbox)
        try:
            return run.go(settings)
        finally:
            run.close()


class _Run:
    """The course's run, step by step: domain, simulator, submission, the run, its evidence."""

    def __init__(self, course, robot, stopping, folder, sandbox):
        self.course, self.stopping, self.folder = course, stopping, folder
        self.sandbox = sandbox
        self.bag = folder / 'run.mcap'
        self.domain = CourseDomain(self.bag, robot, course)
        # The grader's own files of the run, and the submission's working folder: its home,
        # with its copy of the waypoint file; both go at the end. Sealed, the submission runs
        # as a uid of its own (and with namespaces its home is its own /tmp's).
        self.private = Path(tempfile.mkdtemp(prefix='grade_lab-'))
        self.working = Path(tempfile.mkdtemp(prefix='grade_lab-work-'))
        shutil.copyfile(course.waypoint_file, self.working / 'waypoints.txt')
        self.uid = sandbox.uids.take() if sandbox.sealed else None
        self.watch = RunWatch(course, sandbox, self.uid)
        self.home = SANDBOX_HOME if sandbox.mode == NAMESPACES else str(self.working)
        self.simulator = self.link = self.submission = None
        self._last_heard = (time.monotonic(), 0)

    def spin(self, condition, timeout):
        """Spin until condition() holds; False after timeout, or if grading stops first."""
        deadline = time.monotonic() + timeout
        while not condition():
            if self.stopping.is_set() or time.monotonic() > deadline:
                return False
            self.watch.look(self.domain, self.simulator, self.submission)
            self.domain.spin_once()
        return True

    def go(self, settings: RunSettings) -> RunEvidence:
        """Run the course: its domain, the simulator, the submission, the run to its end."""
        try:
            if self.sandbox.mode == NAMESPACES:
                self.domain.open_sealed()
            else:
                self.domain.take_empty()
            environment = course_environment(self.domain.domain_id, self.sandbox.sealed)
            marker = uuid.uuid4().hex
            self._start_simulator(settings, environment, marker)
            self._start_submission(settings, environment, marker)
            if not self.link.play():
                raise GradingError('the simulator did not start playing')
            timed_out = self._until_over()
            self._catch_up()
            self.watch.check_flood(self.domain)
        except Foul as foul:
            self.watch.foul(str(foul))
            return self._result(self._stop_submission())
        except GradingError as error:
            return self._result(self._stop_submission(), str(error))
        if self.stopping.is_set():
            return self._result(self._stop_submission(), 'grading was interrupted')
        outcome = self._stop_submission(timed_out)
        if self.domain.recorded.failure:
            return self._result(outcome, 'the run could not be recorded: '
                                f'{self.domain.recorded.failure}')
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
                         and self.domain.recorder.simulator_matched, SIMULATOR_START):
            raise GradingError("the simulator's ground truth and stall topics did not "
                               f'show within {SIMULATOR_START:g} s')
        # Read by now: the file names the course's world, so it goes before the submission.
        shutil.rmtree(self.private, ignore_errors=True)
        self.watch.simulator_started(self.domain)

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
        if self.spin(lambda: self.domain.recorder.status_publishers
                     or not self.submission.running,
                     STATUS_PUBLISHER_WAIT):
            self.spin(lambda: False, MATCH_SETTLE)

    def _result(self, outcome, error=''):
        """Return the run's evidence: the truth the simulator sent up to now, the statuses."""
        self.close()
        link, recorded = self.link, self.domain.recorded
        return RunEvidence(outcome, self.bag, error, link.truth() if link else [],
                           list(recorded.statuses), link.limits if link else None,
                           tuple(self.watch.fouls), recorded.submitted_map,
                           (recorded.bag_note,) if recorded.bag_note else ())

    def _until_over(self):
        """Spin until the run is over; return whether the time limit ended it."""
        deadline = time.monotonic() + self.course.time_limit

        def over():
            now = time.monotonic()
            ended = self.domain.recorder.ended_at
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
        recorder = self.domain.recorder

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
        self.domain.close_recorder()
        if self.submission is None:
            return ProcessOutcome(start_error='not started: the grader failed first')
        if self.submission.start_error:
            return ProcessOutcome(start_error=self.submission.start_error)
        seconds = self.submission.seconds
        if self.submission.disk_full():
            self.watch.foul(f'filled its working space: the {self.sandbox.disk_mb} MB of /tmp '
                            '(with /dev/shm and /var/tmp) it may write (grade_lab --disk)')
        ended_by, stop_seconds, leftovers = self.submission.stop()
        return ProcessOutcome(ended_by=ended_by, exit_code=self.submission.exit_code,
                              seconds=seconds, stop_seconds=stop_seconds, timed_out=timed_out,
                              last_lines=tuple(self.submission.last_lines),
                              leftovers=tuple(leftovers))

    def close(self):
        """Stop whatever of the run still goes (the submission before); again is harmless."""
        self.domain.close_recorder()
        if self.submission is not None and self.submission.running:
            self._stop_submission()
        if self.link is not None:
            self.link.close()
        if self.simulator is not None:
            self.simulator.stop()
        self.domain.close()
        shutil.rmtree(self.private, ignore_errors=True)
        shutil.rmtree(self.working, ignore_errors=True)
        if self.uid is not None:
            self.sandbox.uids.give_back(self.uid)
            self.uid = None
