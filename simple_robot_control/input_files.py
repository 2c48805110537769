"""
Reading the files users give the package, and checking where it writes, one line per refusal.

Only regular files of sane size are opened, so a FIFO, /dev/zero or a huge file is refused
before anything is read rather than hanging or exhausting memory; text may start with the
UTF-8 byte order mark that some editors write. YAML is bounded three ways before it becomes
Python objects: its length, its nesting depth and its element count, so no document can recurse,
exhaust memory or hold the caller for long (16 KB of YAML parse in a few milliseconds with
libyaml). YAML numbers may be written as 1e12, as in YAML 1.2, not only as 1.0e+12.
"""

import os
import re
import stat

import yaml

MAX_TEXT_BYTES = 10 << 20
# A robot or obstacle description, a map file: the largest of STDR's robot files is 6 KB.
MAX_DESCRIPTION_BYTES = 16 << 10
# A file listing many items (a robot list of a swarm), read once at start.
MAX_LIST_BYTES = 1 << 20
# Every format of the package nests less than ten levels deep.
MAX_NESTING = 32
MAX_ELEMENTS = 200_000
# A folder searched for YAML files (worlds, spawnables): its entries looked at, files taken.
MAX_FOLDER_ENTRIES = 10_000
MAX_FOLDER_FILES = 1_000

_FLOAT_WITHOUT_DOT = re.compile(r'^[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+$')


class _TooDeep(yaml.YAMLError):
    """Nesting beyond MAX_NESTING, met while composing."""


class _PythonLoader(yaml.SafeLoader):
    """PyYAML's safe loader, composing no deeper than MAX_NESTING (it recurses per level)."""

    _depth = 0

    def compose_node(self, parent, index):
        self._depth += 1
        try:
            if self._depth > MAX_NESTING:
                raise _TooDeep()
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


# libyaml, where PyYAML was built with it (PyPI's wheels and Debian's package are): several
# times faster, and it composes without recursing in Python.
_Loader = getattr(yaml, 'CSafeLoader', _PythonLoader) if yaml.__with_libyaml__ else (
    _PythonLoader)


class _Reader(_Loader):
    """The safe loader, reading 1e12 and 5E-3 as numbers (PyYAML wants a dot)."""


_Reader.add_implicit_resolver('tag:yaml.org,2002:float', _FLOAT_WITHOUT_DOT,
                              list('-+0123456789'))


def check_file(path: str | os.PathLike, what: str, error_type: type[Exception],
               max_bytes: int) -> None:
    """Raise error_type unless path is a regular file of at most max_bytes."""
    try:
        status = os.stat(path)
    except OSError as error:
        raise error_type(f'{path}: cannot read {what}: {error.strerror}') from None
    if not stat.S_ISREG(status.st_mode):
        raise error_type(f'{path}: {what} is not a regular file')
    if status.st_size > max_bytes:
        raise error_type(f'{path}: {what} is too large ({status.st_size:,} bytes; at most '
                         f'{max_bytes:,})')


def is_regular_file(path: str | os.PathLike) -> bool:
    """Whether path is a regular file (not a folder, FIFO or device), without opening it."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def yaml_files(folder: str | os.PathLike, suffixes: tuple[str, ...] = ('.yaml', '.yml')
               ) -> tuple[list, str]:
    """
    Return a folder's regular files named *.yaml (or suffixes), sorted, and what was left out.

    FIFOs, devices and folders named *.yaml are skipped without being opened; a folder
    larger than MAX_FOLDER_ENTRIES or MAX_FOLDER_FILES is read that far.
    """
    found, seen = [], 0
    try:
        with os.scandir(folder) as entries:
            for entry in entries:
                seen += 1
                if seen > MAX_FOLDER_ENTRIES or len(found) >= MAX_FOLDER_FILES:
                    note = (f'{folder}: only its first {MAX_FOLDER_ENTRIES:,} entries were '
                            f'looked at, taking at most {MAX_FOLDER_FILES:,} files')
                    return sorted(found), note
                if entry.name.endswith(suffixes) and entry.is_file():
                    found.append(entry.path)
    except OSError as error:
        return [], f'{folder}: cannot read it: {error.strerror}'
    return sorted(found), ''


def read_text(path: str | os.PathLike, what: str, error_type: type[Exception],
              max_bytes: int = MAX_TEXT_BYTES) -> str:
    """Return the text of a UTF-8 file (a leading byte order mark is dropped)."""
    path = os.fspath(path)
    check_file(path, what, error_type, max_bytes)
    try:
        with open(path, encoding='utf-8-sig') as stream:
            return stream.read(max_bytes + 1)
    except OSError as error:
        raise error_type(f'{path}: cannot read {what}: {error.strerror}') from None
    except UnicodeDecodeError as error:
        raise error_type(f'{path}: {what} is not a text file ({error.reason})') from None


def read_yaml(path: str | os.PathLike, what: str, error_type: type[Exception],
              max_bytes: int = MAX_DESCRIPTION_BYTES) -> object:
    """
    Return the parsed contents of a YAML file of at most max_bytes.

    A file that cannot be read or parsed raises error_type with one line naming the file,
    the line where the YAML breaks, and what the file was meant to be.
    """
    path = os.fspath(path)
    return parse_yaml(read_text(path, what, error_type, max_bytes), path, what, error_type,
                      max_bytes)


def parse_yaml(text: str, source: str, what: str, error_type: type[Exception],
               max_chars: int = MAX_DESCRIPTION_BYTES) -> object:
    """
    Return the parsed YAML text; error_type names source and the line where it breaks.

    Text longer than max_chars, nested deeper than MAX_NESTING or holding more than
    MAX_ELEMENTS values (aliases counted each time they are used) is refused before any
    Python object is built from it.
    """
    if len(text) > max_chars:
        raise error_type(f'{source}: {what} is too large ({len(text):,} characters; at most '
                         f'{max_chars:,})')
    loader = _Reader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        problem = _shape_problem(node)
        if problem:
            raise error_type(f'{source}: {what} {problem}')
        return loader.construct_document(node)
    except _TooDeep:
        raise error_type(f'{source}: {what} is nested more than {MAX_NESTING} levels '
                         'deep') from None
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        line = f':{mark.line + 1}' if mark is not None else ''
        reason = 'is nested too deeply' if 'nesting depth' in str(error) else 'is not valid YAML'
        raise error_type(f'{source}{line}: {what} {reason}') from None
    finally:
        loader.dispose()


def _shape_problem(root):
    """Say how a composed YAML document is too deep or too large, or return ''."""
    pending = [(root, 1)]
    elements = 0
    while pending:
        node, depth = pending.pop()
        elements += 1
        if depth > MAX_NESTING:
            return f'is nested more than {MAX_NESTING} levels deep'
        if elements > MAX_ELEMENTS:
            return f'holds more than {MAX_ELEMENTS:,} values'
        if isinstance(node, yaml.SequenceNode):
            pending += [(child, depth + 1) for child in node.value]
        elif isinstance(node, yaml.MappingNode):
            pending += [(part, depth + 1) for pair in node.value for part in pair]
    return ''


def output_problem(path: str | os.PathLike, inputs: tuple | list = ()) -> str | None:
    """
    Say why a file may not be written at path, or return None.

    Nothing the package writes may destroy anything: an existing path must be a regular
    file (not a folder, FIFO or device) and none of the run's inputs, and a new one must go
    into an existing folder.
    """
    path = os.fspath(path)
    if not path:
        return 'no file name given'
    try:
        status = os.stat(path)
    except FileNotFoundError:
        folder = os.path.dirname(os.path.abspath(path))
        return None if os.path.isdir(folder) else f'{folder} is not an existing folder'
    except OSError as error:
        return f'cannot write there: {error.strerror}'
    if stat.S_ISDIR(status.st_mode):
        return 'is a folder, not a file'
    if not stat.S_ISREG(status.st_mode):
        return 'is not a regular file (a FIFO or a device): refusing to write to it'
    for source in inputs:
        try:
            if source and os.path.samefile(path, source):
                return f'is {source}, an input of this run: refusing to overwrite it'
        except OSError:
            continue
    return None
