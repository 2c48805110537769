"""The two ways a course's run ends early: the grader could not, or the submission fouled."""


class GradingError(Exception):
    """The grader could not run a course; not the submission's doing."""


class Foul(Exception):
    """The submission did what ends a run at once and fails the course (the message says what)."""
