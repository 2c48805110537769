"""
Ctrl-C and SIGTERM held from the interpreter's first lines until an executable can handle them.

The PyPI ROS wheels start every interpreter twice: a .pth file of theirs re-executes it with
their library path, and a signal that Python's own handler has taken just before that exec is
lost with the old image (the program then runs on). A signal before the package's handlers
exist would end it by the default action, or with a KeyboardInterrupt traceback from inside
site or an import. So the .pth installed beside theirs (it sorts first) blocks SIGINT and
SIGTERM, for an executable of this package only; an exec keeps them blocked, as it keeps a
blocked signal pending; executables.py unblocks them once its handlers are set, and a
signal that came meanwhile ends the program then, exit 0. Anything else Python runs is left
alone: the .pth blocks both signals in its first statement, the shortest window there is, and
this module unblocks them again for any other program. No imports beyond the standard
library's smallest: this runs before site is done.
"""

import signal
import sys

HELD = (signal.SIGINT, signal.SIGTERM)


def is_package_executable(argv: list[str], packages: tuple[str, ...]) -> bool:
    """
    Whether argv (the interpreter's, as started) runs one of the package's console scripts.

    Each imports its entry point from one of packages' executables modules (setup.py).
    """
    if len(argv) < 2:
        return False
    try:
        with open(argv[1], 'rb') as script:
            head = script.read(1024)
    except OSError:
        return False
    return any(f'from {package}.executables import '.encode() in head for package in packages)


def keep_held_for_package_executables(packages: tuple[str, ...]) -> None:
    """Keep SIGINT and SIGTERM blocked only if this interpreter runs an executable of ours."""
    if not is_package_executable(getattr(sys, 'orig_argv', []), packages):
        release_signals()


def release_signals() -> None:
    """Unblock them: one that came while they were held is handled now."""
    signal.pthread_sigmask(signal.SIG_UNBLOCK, HELD)
