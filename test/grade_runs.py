"""grade_lab run as a user would, and nothing it started left running afterwards."""

import os
import signal
import uuid

from processes import run
import psutil

TAG = 'GRADE_LAB_TEST_TAG'


def tagged_processes(tag, folder=None):
    """
    Return the running processes of a grading: tagged in their environment, or working in folder.

    A submission runs with an environment of grade_lab's making (the tag is not in it), in its
    folder of the test's.
    """
    found = []
    for process in psutil.process_iter():
        try:
            if process.status() == psutil.STATUS_ZOMBIE or process.pid == os.getpid():
                continue
            if process.environ().get(TAG) == tag or (
                    folder is not None and process.cwd().startswith(str(folder))):
                found.append(process)
        except psutil.Error:
            continue
    return found


def ignore_sigint():
    """Start as a background job of a shell script starts: with SIGINT ignored."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def grade(*arguments, timeout=600, cwd=None, sigint_ignored=False):
    """
    Run grade_lab with a tag its processes inherit; fail if any of them outlives it.

    The submission's folder is made readable by others, as a checkout is (pytest makes its
    folders 0700): as root, grade_lab runs the submission as a uid of its own.
    """
    if cwd is not None:
        os.chmod(cwd, 0o755)
    tag = uuid.uuid4().hex
    os.environ[TAG] = tag
    try:
        result = run('grade_lab', *map(str, arguments), timeout=timeout, cwd=cwd,
                     preexec_fn=ignore_sigint if sigint_ignored else None)
    finally:
        del os.environ[TAG]
    left = tagged_processes(tag, cwd)
    for process in left:
        process.kill()
    assert not left, f'processes left behind: {left}\n{result.stdout}\n{result.stderr}'
    return result


def write_course(folder, name, waypoints, **settings):
    folder.mkdir(exist_ok=True)
    (folder / f'{name}.txt').write_text(waypoints + '\n')
    if settings:
        (folder / f'{name}.yaml').write_text(''.join(f'{key}: {value}\n'
                                                     for key, value in settings.items()))
