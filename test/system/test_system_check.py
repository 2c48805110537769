"""make's first step, scripts/check_system.sh: what this machine lacks, named in one line."""

import os
from pathlib import Path
import subprocess

import pytest

CHECK = Path(__file__).resolve().parents[2] / 'scripts' / 'check_system.sh'


def os_ids():
    try:
        text = Path('/etc/os-release').read_text()
    except OSError:
        return set()
    fields = dict(line.split('=', 1) for line in text.splitlines() if '=' in line)
    return {value for key in ('ID', 'ID_LIKE') for value in
            fields.get(key, '').strip('"').split()}


ON_DEBIAN = bool(os_ids() & {'debian', 'ubuntu'})


def check(tmp_path, **environment):
    return subprocess.run([str(CHECK)], capture_output=True, text=True, timeout=30,
                          env={**os.environ, **environment}, cwd=tmp_path)


def test_this_machine_has_what_the_install_builds_with(tmp_path):
    result = check(tmp_path)
    assert (result.returncode, result.stdout, result.stderr) == (0, '', '')


@pytest.fixture
def python_without_venv_or_headers(tmp_path):
    """Give a python3 of 3.10 or later with no ensurepip nor Python.h (a bare Debian's)."""
    stub = tmp_path / 'python3'
    stub.write_text('#!/bin/sh\ncase "$2" in *ensurepip* | *sysconfig*) exit 1 ;; esac\nexit 0\n')
    stub.chmod(0o755)
    return stub


def test_what_is_missing_is_one_line_with_the_command_that_installs_it(
        tmp_path, python_without_venv_or_headers):
    result = check(tmp_path, PYTHON3=str(python_without_venv_or_headers),
                   CC=str(tmp_path / 'no-cc'), CXX=str(tmp_path / 'no-cxx'))
    assert result.returncode == 2 and result.stdout == ''
    [line] = result.stderr.splitlines()
    assert line.startswith('make: this machine lacks what the install builds with: ')
    if ON_DEBIAN:
        sudo = '' if os.geteuid() == 0 else 'sudo '
        assert line.endswith('python3-venv python3-dev gcc g++; install with `'
                             f'{sudo}apt-get install --no-install-recommends python3-venv '
                             'python3-dev gcc g++` and run make again')


def test_an_old_python_is_named_alone(tmp_path):
    old = tmp_path / 'python3'
    old.write_text('#!/bin/sh\nexit 1\n')
    old.chmod(0o755)
    result = check(tmp_path, PYTHON3=str(old))
    assert result.returncode == 2
    if ON_DEBIAN:
        assert 'builds with: python3; install with' in result.stderr


@pytest.mark.skipif(not ON_DEBIAN, reason='the package names checked are Debian and Ubuntu ones')
def test_the_packages_listed_for_a_set_up_are_the_ones_named():
    result = subprocess.run([str(CHECK), '--packages'], capture_output=True, text=True,
                            timeout=30)
    assert result.stdout.split() == ['python3', 'python3-venv', 'python3-dev', 'gcc', 'g++']
