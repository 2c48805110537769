"""
A course's verdict, and a submission's: the checks, the figures, the status. No ROS here.

A course passes when every check does; it is an error, not a failure, when the grader could
not run it (the simulator would not start, the bag cannot be read): that is no fault of the
submission's, and a grading with an error is not a pass either.
"""

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from lab_grader.simulator_link import SpeedLimits
from lab_grader.verdicts import Check, Judge, ProcessOutcome
from simple_robot_control.occupancy_map import OccupancyMap
from waypoint_lab.course import Course
from waypoint_lab.rules import WAYPOINTS_TASK
from waypoint_lab.run import assemble_run, Run

if TYPE_CHECKING:
    from lab_grader.task_checks import TaskPicture

PASS, FAIL, ERROR = 'pass', 'fail', 'error'


@dataclass
class CourseVerdict:
    """How a submission did on one course."""

    course: Course
    checks: list[Check] = field(default_factory=list)
    outcome: ProcessOutcome = field(default_factory=ProcessOutcome)
    error: str = ''
    time_taken: float | None = None
    path_length: float | None = None
    folder: Path | None = None
    picture_problem: str = ''
    notes: tuple[str, ...] = ()
    task_picture: 'TaskPicture | None' = field(default=None, repr=False)
    run: Run | None = field(default=None, repr=False)

    @property
    def status(self) -> str:
        if self.error:
            return ERROR
        return PASS if self.checks and all(check.passed for check in self.checks) else FAIL

    @property
    def score(self) -> float:
        return self.course.points if self.status == PASS else 0.0

    @property
    def failures(self) -> list[Check]:
        return [check for check in self.checks if not check.passed]


@dataclass
class SubmissionVerdict:
    """How one submission (a group's) did on every course."""

    name: str
    courses: list[CourseVerdict] = field(default_factory=list)

    @property
    def status(self) -> str:
        statuses = {verdict.status for verdict in self.courses}
        return ERROR if ERROR in statuses else FAIL if FAIL in statuses or not statuses else PASS

    @property
    def score(self) -> float:
        return sum(verdict.score for verdict in self.courses)

    @property
    def max_score(self) -> float:
        return sum(verdict.course.points for verdict in self.courses)


@dataclass
class RunEvidence:
    """
    What a course's run left: how the submission ended, its bag, and the judge's evidence.

    truth is the simulator's path as its private socket gave it ((sim s, pose, wall ns sent,
    stalled) per step), statuses every robot_status message ((wall ns sent, text)); submitted_map
    a mapping submission's last map (or why it was none); fouls are
    lines that each fail the course; error a failure of the grader's (or of another program's),
    not the submission's. The bag is the run's record for people, never the judge's evidence;
    notes say what it lacks (cut short at its size limit).
    """

    outcome: ProcessOutcome
    bag: Path
    error: str = ''
    truth: list = field(default_factory=list)
    statuses: list = field(default_factory=list)
    limits: SpeedLimits | None = None
    fouls: tuple[str, ...] = ()
    submitted_map: OccupancyMap | str | None = None
    notes: tuple[str, ...] = ()


def grade_course(course: Course, evidence: RunEvidence,
                 robot_name: str = 'robot0') -> CourseVerdict:
    """Judge a course's run from its evidence (and keep the run it makes)."""
    verdict = CourseVerdict(course, outcome=evidence.outcome, error=evidence.error,
                            folder=evidence.bag.parent, notes=evidence.notes)
    run = verdict.run = assemble_run(course, evidence.truth, evidence.statuses, robot_name)
    if evidence.error and not evidence.fouls:
        return verdict
    verdict.error = ''
    if run.missing_steps:
        verdict.error = (f"the simulator's socket lost {run.missing_steps} true poses: grade "
                         'again')
        return verdict
    judge = Judge(course, run, evidence.outcome, evidence.fouls, evidence.limits)
    task_checks, verdict.task_picture = _judge_task(course, run, evidence.submitted_map)
    verdict.checks = judge.checks(task_checks)
    verdict.time_taken, verdict.path_length = judge.time_taken, judge.path_length
    return verdict


def _judge_task(course, run, submitted_map):
    """
    Return the checks and picture a coursework's task adds; the lab's task adds none.

    The courseworks' judges (scipy, numba: a second of import) load only where one is graded,
    so a grading of the lab, or a command line refused, starts without them.
    """
    if course.task == WAYPOINTS_TASK:
        return [], None
    from lab_grader.task_checks import judge_task
    return judge_task(course, run, submitted_map)
