"""Reading the package's YAML inputs (maps, robots, robot lists) with one-line errors."""

import os

import yaml


def read_yaml(path, what, error_type):
    """
    Return the parsed contents of a YAML file.

    A file that cannot be read or parsed raises error_type with one line naming the file,
    the line where the YAML breaks, and what the file was meant to be.
    """
    path = os.fspath(path)
    try:
        with open(path, encoding='utf-8') as stream:
            return yaml.safe_load(stream)
    except OSError as error:
        raise error_type(f'{path}: cannot read {what}: {error.strerror}') from None
    except UnicodeDecodeError as error:
        raise error_type(f'{path}: {what} is not a text file ({error.reason})') from None
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        line = f':{mark.line + 1}' if mark is not None else ''
        raise error_type(f'{path}{line}: {what} is not valid YAML') from None
