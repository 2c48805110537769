"""What a sandbox hides, shows and refuses, decided before any submission runs (sandbox.py)."""

import os
from pathlib import Path
import shutil
import tempfile

from lab_grader.sandbox import (choose_mode, NAMESPACES, SAME_USER, SandboxPolicy, UID_RANGE,
                                UidPool, untraversable_ancestor)


def test_a_folder_others_cannot_pass_is_found_above_a_path():
    top = Path(tempfile.mkdtemp(prefix='sandbox-policy-', dir='/tmp'))
    try:
        top.chmod(0o755)
        closed = top / 'closed'
        (closed / 'inside' / 'deeper').mkdir(parents=True)
        closed.chmod(0o700)
        assert untraversable_ancestor(str(closed / 'inside' / 'deeper')) == str(closed)
        assert untraversable_ancestor(str(top / 'closed')) is None
        assert untraversable_ancestor('/usr/lib') is None
    finally:
        shutil.rmtree(top)


def test_the_interpreter_under_a_closed_home_is_covered_and_shown_again(tmp_path):
    policy = SandboxPolicy(NAMESPACES, hidden=('/srv/courses',), needed=('/root/.pyenv/x',))
    group = tmp_path / 'group'
    group.mkdir()
    closed = untraversable_ancestor(str(group))  # pytest's own folder is 0700
    jail = policy.jail(2_000_000_001, str(group), {'waypoints.txt': '/somewhere'})
    closed_root = not os.stat('/root').st_mode & 0o001
    assert jail['cover'] == sorted(({'/root'} if closed_root else set())
                                   | ({closed} if closed else set()))
    assert ('/root/.pyenv/x' in jail['expose']) == closed_root
    assert (str(group) in jail['expose']) == bool(closed), 'shown again below a closed folder'
    assert (jail['uid'], jail['hide'], jail['copy_in']) == (
        2_000_000_001, ['/srv/courses'], {'waypoints.txt': '/somewhere'})


def test_a_hidden_folder_holding_what_the_submission_needs_is_refused(tmp_path):
    group = tmp_path / 'group'
    group.mkdir()
    group.chmod(0o755)
    policy = SandboxPolicy(NAMESPACES, hidden=(str(tmp_path),))
    assert policy.problem(str(group)) == (
        f'{tmp_path} must be hidden from the submissions, but holds {group}, which they need: '
        'keep the courses and the reports apart')
    group.chmod(0o700)
    assert 'mode 700: the uid of its own that it runs as cannot read it' in policy.problem(
        str(group))
    assert SandboxPolicy(SAME_USER, hidden=(str(tmp_path),)).problem(str(group)) == ''


def test_no_two_courses_get_one_uid_nor_one_a_process_has():
    pool = UidPool()
    taken = {pool.take() for _ in range(50)}
    assert len(taken) == 50 and all(uid in UID_RANGE for uid in taken)
    pool.give_back(taken.pop())


def test_none_asked_is_the_same_user_saying_so():
    assert choose_mode('none') == (SAME_USER, 'asked for by --sandbox none')
