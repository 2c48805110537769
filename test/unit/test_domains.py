"""Domains claimed by one process are never handed to another while it holds them."""

import os
import subprocess
import sys

from lab_grader import domains
from lab_grader.domains import claim_domain, NoDomainLeft
import pytest


@pytest.fixture
def three_domains(monkeypatch, tmp_path):
    """Claim from domains 7, 8 and 9 only, with locks of this test's own."""
    monkeypatch.setattr(domains, 'DOMAINS', range(7, 10))
    monkeypatch.setattr(domains, 'LOCK_FOLDER', tmp_path / 'locks')
    monkeypatch.delenv('ROS_DOMAIN_ID', raising=False)


def test_claims_differ_until_released(three_domains):
    claims = [claim_domain() for _ in range(3)]
    assert sorted(claim.domain_id for claim in claims) == [7, 8, 9]
    with pytest.raises(NoDomainLeft, match='all 3 ROS domains of 7 to 9 are in use'):
        claim_domain()
    claims[1].release()
    assert claim_domain().domain_id == claims[1].domain_id


def test_a_domain_held_by_another_process_or_in_the_environment_is_avoided(
        three_domains, monkeypatch):
    holder = subprocess.Popen(
        [sys.executable, '-c', 'import fcntl, os, signal; '
         f'fd = os.open({str(domains.LOCK_FOLDER / "8.lock")!r}, os.O_RDWR | os.O_CREAT); '
         'fcntl.flock(fd, fcntl.LOCK_EX); print("held", flush=True); signal.pause()'],
        stdout=subprocess.PIPE, text=True)
    try:
        domains.LOCK_FOLDER.mkdir()
        assert holder.stdout.readline() == 'held\n'
        monkeypatch.setenv('ROS_DOMAIN_ID', '7')
        for _ in range(5):
            claim = claim_domain(avoid=(1,))
            assert claim.domain_id == 9
            claim.release()
    finally:
        holder.kill()
        holder.wait()
    assert {claim_domain().domain_id for _ in range(2)} == {8, 9}, 'a lock goes with its process'


def test_a_child_process_does_not_keep_the_domain(three_domains):
    """A child that inherited the lock would hold the domain after its parent let it go."""
    claims = [claim_domain() for _ in range(3)]
    child = subprocess.Popen([sys.executable, '-c', 'print("started", flush=True); '
                              'import signal; signal.pause()'], close_fds=False,
                             stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline() == 'started\n'
        claims[0].release()
        assert claim_domain().domain_id == claims[0].domain_id
    finally:
        child.kill()
        child.wait()


def test_whatever_stands_in_a_lock_files_place_is_skipped_and_new_files_are_everyones(
        three_domains):
    """A folder, a FIFO or a link planted as a lock file costs its domain, nothing more."""
    domains.LOCK_FOLDER.mkdir()
    (domains.LOCK_FOLDER / '7.lock').mkdir()
    os.mkfifo(domains.LOCK_FOLDER / '8.lock')
    old_mask = os.umask(0o022)
    try:
        claim = claim_domain()
    finally:
        os.umask(old_mask)
    assert claim.domain_id == 9
    assert (domains.LOCK_FOLDER / '9.lock').stat().st_mode & 0o777 == 0o666
    (domains.LOCK_FOLDER / '7.lock').rmdir()
    (domains.LOCK_FOLDER / '7.lock').symlink_to(domains.LOCK_FOLDER / '9.lock')
    with pytest.raises(NoDomainLeft):
        claim_domain()
