"""The exit codes of the package's executables, and what each means to a user."""

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_BAD_INPUT = 2

MEANINGS = {
    EXIT_OK: 'finished (or stopped on request)',
    EXIT_FAILED: 'the run failed (ABORTED, or no simulator answering); see its log above',
    EXIT_BAD_INPUT: 'refused its input (a parameter, file or argument); see the error above',
}


def describe_exit(name: str, code: int) -> str:
    """Return one line saying how an executable ended, for launch files and scripts."""
    meaning = MEANINGS.get(code, 'was killed or crashed' if code < 0 else 'ended unexpectedly')
    return f'{name} exited with code {code}: {meaning}'
