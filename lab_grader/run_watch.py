"""
What ends a course's run while it goes: intruders, a flood of statuses, a simulator ended.

Whoever publishes on the simulator's topics besides the simulator is named (publishers.py):
the submission's doing is a foul (the course fails), another program in the domain an error.
A simulator that ends during the run by a signal the grader did not send was ended by the
submission: a foul too.
"""

import os
import time

from lab_grader.course_domain import CourseDomain
from lab_grader.publishers import find_intruders, socket_owners, strangers
from lab_grader.run_errors import Foul, GradingError
from lab_grader.sandbox import NAMESPACES, SandboxPolicy
from lab_grader.submission_process import Submission
from lab_grader.supervision import Supervised
from waypoint_lab.course import Course

# How often the graph is read for intruders, and the domain's sockets looked at (wall seconds).
WATCH_PERIOD = 0.1
SOCKETS_PERIOD = 1.0


class RunWatch:
    """The fouls and strangers seen so far in one run, and the looks that find them."""

    def __init__(self, course: Course, sandbox: SandboxPolicy, uid: int | None):
        self._course, self._sandbox, self._uid = course, sandbox, uid
        self.simulator_gids = set()
        self.fouls, self.strangers = [], []
        self._watched_at = self._sockets_at = 0.0

    def simulator_started(self, domain: CourseDomain) -> None:
        """Note the simulator's endpoints: the domain holds the simulator and the grader alone."""
        recorder = domain.recorder
        self.simulator_gids = {publisher.gid for publisher
                               in recorder.publishers(recorder.watched)}

    def foul(self, line: str) -> None:
        """Note a foul once."""
        if line not in self.fouls:
            self.fouls.append(line)

    def look(self, domain: CourseDomain, simulator: Supervised | None,
             submission: Submission | None) -> None:
        """Raise Foul or GradingError if the run must end now; called at every spin."""
        self._check_simulator(simulator, submission)
        if submission is None or time.monotonic() - self._watched_at < WATCH_PERIOD:
            return
        self._watched_at = time.monotonic()
        recorder = domain.recorder
        outsiders = []
        if self._sandbox.mode != NAMESPACES and (
                time.monotonic() - self._sockets_at >= SOCKETS_PERIOD):
            self._sockets_at = time.monotonic()
            run_pids = {os.getpid(), simulator.pid} | submission.pids()
            outsiders = strangers(socket_owners(domain.domain_id), run_pids, self._uid)
        found = find_intruders(recorder.publishers(recorder.watched), self.simulator_gids,
                               outsiders)
        for line in found.fouls:
            self.foul(line)
        self.strangers += [line for line in found.strangers if line not in self.strangers]
        self.check_flood(domain)
        if self.fouls:
            raise Foul(self.fouls[0])
        if self.strangers:
            raise GradingError(f"{self.strangers[0]}: not the submission's doing; grade again")

    def check_flood(self, domain: CourseDomain) -> None:
        """Raise Foul once the submission has sent more statuses than any honest run."""
        recorder = domain.recorder
        if recorder.flooded:
            self.foul(f'sent {recorder.sent_statuses} messages on robot_status, more than '
                      f'{recorder.status_limit} (an honest run sends '
                      f'{len(self._course.waypoints) + 2}): the run was ended there')
            raise Foul(self.fouls[0])

    @staticmethod
    def _check_simulator(simulator, submission):
        if simulator is None or simulator.running:
            return
        code = simulator.exit_code
        if code is not None and code <= 0 and submission is not None:
            raise Foul(f'the simulator was ended during the run ({_ended_text(code)}), not by '
                       'the grader')
        raise GradingError(f'the simulator ended (exit code {code}): '
                           f'{" | ".join(simulator.last_lines)[-300:]}')


def _ended_text(code):
    return 'exit code 0 after a signal' if code == 0 else f'killed by signal {-code}'
