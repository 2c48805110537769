"""A submission's sandbox as root makes it: what it can see, write, signal and keep (jail.py)."""

import os
from pathlib import Path
import sys

from lab_grader.sandbox import choose_mode, NAMESPACES, needed_paths, SandboxPolicy
from lab_grader.submission_process import Submission
from processes import wait_until
import psutil
import pytest

pytestmark = pytest.mark.skipif(
    os.geteuid() != 0 or choose_mode('auto')[0] != NAMESPACES,
    reason='a sandbox of namespaces takes root, and a kernel that allows them')

LOOK = """
id -u; id -G
echo "sees: $(ls -A courses | tr '\\n' ' ')|"
echo "home: $HOME $(cat $HOME/waypoints.txt)"
touch /var/tmp/x 2>/dev/null && echo "wrote var_tmp"
touch courses/planted 2>/dev/null || echo "courses refused"
touch "$SUBMISSION/planted" 2>/dev/null || echo "own folder refused"
touch /etc/planted 2>/dev/null || echo "etc refused"
echo "processes: $(ls /proc | grep -c '^[0-9]')"
kill -9 1 2>/dev/null || echo "first refused"
grep CapBnd /proc/self/status
grep NoNewPrivs /proc/self/status
python3 -c 'print("python runs")'
setsid python3 -c 'import signal; signal.signal(signal.SIGINT, signal.SIG_DFL)
signal.pause()' &
"""


def run_in_sandbox(folder, script):
    """Run a shell script as a sandboxed submission in folder; return (exit code, output)."""
    policy = SandboxPolicy(NAMESPACES, (str(folder / 'courses'),), needed_paths(os.environ),
                           disk_mb=8)
    waypoints = folder / 'waypoints.txt'
    waypoints.write_text('1 2 0\n')
    uid = policy.uids.take()
    jail = policy.jail(uid, str(folder), {'waypoints.txt': str(waypoints)})
    environment = dict(os.environ, HOME='/tmp/work', SUBMISSION=str(folder),
                       PATH=f'{Path(sys.executable).parent}:/usr/bin:/bin')
    process = Submission(['sh', '-c', script], 'sandbox-test', folder / 'output.txt',
                         cwd=str(folder), env=environment, jail=jail)
    try:
        wait_until(lambda: not process.running, 'the end of the sandboxed script', timeout=30)
    finally:
        process.stop()
    policy.uids.give_back(uid)
    return uid, process.exit_code, (folder / 'output.txt').read_text()


def test_the_submission_sees_and_writes_its_own_alone_and_leaves_nothing(tmp_path):
    folder = tmp_path / 'group'
    (folder / 'courses').mkdir(parents=True)
    (folder / 'courses' / 'hidden.txt').write_text('9 9 0\n')
    folder.chmod(0o755)
    uid, code, said = run_in_sandbox(folder, LOOK)
    assert code == 0, said
    lines = said.splitlines()
    assert lines[:2] == [str(uid), str(uid)], said
    assert 'sees: |' in said, 'the courses inside its own folder are hidden'
    assert 'home: /tmp/work 1 2 0' in said and 'wrote var_tmp' in said
    for refused in ('courses refused', 'own folder refused', 'etc refused', 'first refused'):
        assert refused in said, said
    seen = int(said.split('processes: ')[1].split()[0])
    assert seen < 8, f'it sees {seen} processes: its own alone (reaper, shells, ls, grep)'

    assert 'CapBnd:\t0000000000000000' in said and 'NoNewPrivs:\t1' in said
    assert 'python runs' in said, 'the interpreter, under /root, is shown to it'
    assert not (folder / 'courses' / 'planted').exists()
    assert (folder / 'courses' / 'hidden.txt').read_text() == '9 9 0\n'
    assert not [process for process in psutil.process_iter(['uids'])
                if process.info['uids'] and uid in process.info['uids']]
