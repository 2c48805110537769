"""
A course's verdict, and a submission's: the checks, the figures, the status. No ROS here.

A course passes when every check does; it is an error, not a failure, when the grader could
not run it (the simulator would not start, the bag cannot be read): that is no fault of the
submission's, and a grading with an error is not a pass either.
"""

from dataclasses import dataclass, field
from pathlib import Path

from lab_grader.verdicts import Check, Judge, ProcessOutcome
from waypoint_lab.course import Course
from waypoint_lab.run import read_run, Run, RunError

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


def grade_course(course: Course, outcome: ProcessOutcome, bag: Path, error: str = '',
                 robot_name: str = 'robot0') -> CourseVerdict:
    """Judge a course's run from its bag and the submission's outcome (and keep what it read)."""
    verdict = CourseVerdict(course, outcome=outcome, error=error, folder=bag.parent)
    try:
        run = verdict.run = read_run(bag, robot_name, 'ground_truth', course)
    except RunError as problem:
        verdict.error = error or f'the run cannot be judged: {problem}'
        return verdict
    if error:
        return verdict
    if run.missing_steps:
        verdict.error = (f"the recorder lost {run.missing_steps} of the simulator's true "
                         'poses (the machine was too busy): grade again with fewer --jobs or a '
                         'lower --real-time-factor')
        return verdict
    judge = Judge(course, run, outcome)
    verdict.checks = judge.checks()
    verdict.time_taken, verdict.path_length = judge.time_taken, judge.path_length
    return verdict
