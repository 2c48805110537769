"""The command line of every executable: a complaint is one line and exit code 2. No ROS here."""

import argparse
import os
import sys
from typing import NoReturn

from simple_robot_control.exit_codes import EXIT_BAD_INPUT


class OneLineParser(argparse.ArgumentParser):
    """
    argparse's parser, whose complaint is one line naming the program, as every refusal is.

    argparse itself prints the usage too, a second block a script must tell apart from the
    error; --help has the usage for whoever wants it.
    """

    def error(self, message: str) -> NoReturn:
        print(f'{self.prog}: error: {message} (see {self.prog} --help)', file=sys.stderr)
        sys.exit(EXIT_BAD_INPUT)


def keep_stdout_for_answers() -> None:
    """
    Keep standard output for this program's own answers; what libraries print goes to stderr.

    Fast DDS prints some errors on C++'s std::cout whatever its profile says (seen: a
    shared-memory port held by a neighbour's process, in `stdr_ctl delete`'s answer), which would
    mix with what a script reads. File descriptor 1 becomes stderr for every library, and
    Python's sys.stdout keeps the real standard output.
    """
    answers = os.dup(1)
    os.dup2(2, 1)
    sys.stdout = os.fdopen(answers, 'w', buffering=1, encoding=sys.stdout.encoding,
                           errors=sys.stdout.errors)
