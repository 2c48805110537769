"""
The courses' files, kept as they were when grading began. No ROS here.

A submission that runs as the grader's user could write where the courses are. The guard reads
every file of the courses' folders (and each course's map and robot file) once, before any
run; after each run it looks again: a file changed or removed is put back as it was, a file
that was not there is removed, and each is named, so that the run that did it fails and no
later run, nor the next grading, meets what a submission made. The bytes are held in memory:
courses are small (at most MAX_BYTES in all).
"""

from collections.abc import Iterable
from pathlib import Path

MAX_BYTES = 256 << 20
MAX_FILES = 10_000


class CourseGuardError(ValueError):
    """The courses' folders hold more than the guard keeps; the message says which and why."""


class CourseGuard:
    """What the courses' files held; check() puts them back and names what changed."""

    def __init__(self, folders: Iterable[Path], files: Iterable[Path]):
        self._folders = sorted({Path(folder).resolve() for folder in folders})
        self._kept = {}
        paths = [Path(file).resolve() for file in files]
        for folder in self._folders:
            paths += self._listing(folder)
        total = 0
        for path in dict.fromkeys(paths):
            if path.is_file():
                data = path.read_bytes()
                total += len(data)
                if total > MAX_BYTES or len(self._kept) >= MAX_FILES:
                    raise CourseGuardError(f'{path.parent}: the courses hold more than '
                                           f'{MAX_FILES:,} files or {MAX_BYTES >> 20} MB')
                self._kept[path] = data

    @staticmethod
    def _listing(folder):
        return [child for child in folder.iterdir() if child.is_file() or child.is_symlink()]

    def check(self) -> list[str]:
        """Put back every kept file that changed, remove every new one; say what each was."""
        found = []
        for path, data in self._kept.items():
            try:
                same = path.is_file() and not path.is_symlink() and path.read_bytes() == data
            except OSError:
                same = False
            if not same:
                found.append(f'{path} was changed or removed during the run (put back)')
                _replace(path, data)
        for folder in self._folders:
            for path in self._listing(folder):
                if path not in self._kept:
                    found.append(f"{path} was made in the courses' folder during the run "
                                 '(removed)')
                    _remove(path)
        return found


def _replace(path, data):
    try:
        _remove(path)
        path.write_bytes(data)
    except OSError:
        pass


def _remove(path):
    try:
        if path.is_dir() and not path.is_symlink():
            return
        path.unlink()
    except OSError:
        pass
