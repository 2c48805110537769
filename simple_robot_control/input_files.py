"""
Reading the files users give the package, each refusal one line naming the file.

Only regular files of sane size are opened, so a FIFO, /dev/zero or a huge file is refused
before anything is read rather than hanging or exhausting memory; text may start with the
UTF-8 byte order mark that some editors write. YAML numbers may be written as 1e12, as in
YAML 1.2, not only as 1.0e+12.
"""

import os
import re
import stat

import yaml

MAX_TEXT_BYTES = 10 << 20


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader, reading 1e12 and 5E-3 as numbers (PyYAML wants a dot)."""


_Loader.add_implicit_resolver(
    'tag:yaml.org,2002:float',
    re.compile(r'^[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+$'), list('-+0123456789'))


def check_file(path, what, error_type, max_bytes):
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


def read_text(path, what, error_type, max_bytes=MAX_TEXT_BYTES):
    """Return the text of a UTF-8 file (a leading byte order mark is dropped)."""
    path = os.fspath(path)
    check_file(path, what, error_type, max_bytes)
    try:
        with open(path, encoding='utf-8-sig') as stream:
            return stream.read()
    except OSError as error:
        raise error_type(f'{path}: cannot read {what}: {error.strerror}') from None
    except UnicodeDecodeError as error:
        raise error_type(f'{path}: {what} is not a text file ({error.reason})') from None


def read_yaml(path, what, error_type):
    """
    Return the parsed contents of a YAML file.

    A file that cannot be read or parsed raises error_type with one line naming the file,
    the line where the YAML breaks, and what the file was meant to be.
    """
    path = os.fspath(path)
    return parse_yaml(read_text(path, what, error_type), path, what, error_type)


def parse_yaml(text, source, what, error_type):
    """Return the parsed YAML text; error_type names source and the line where it breaks."""
    try:
        return yaml.load(text, Loader=_Loader)
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        line = f':{mark.line + 1}' if mark is not None else ''
        raise error_type(f'{source}{line}: {what} is not valid YAML') from None
