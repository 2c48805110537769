"""The command line of every executable: a complaint is one line and exit code 2. No ROS here."""

import argparse
import sys

from simple_robot_control.exit_codes import EXIT_BAD_INPUT


class OneLineParser(argparse.ArgumentParser):
    """
    argparse's parser, whose complaint is one line naming the program, as every refusal is.

    argparse itself prints the usage too, a second block a script must tell apart from the
    error; --help has the usage for whoever wants it.
    """

    def error(self, message):
        print(f'{self.prog}: error: {message} (see {self.prog} --help)', file=sys.stderr)
        sys.exit(EXIT_BAD_INPUT)
