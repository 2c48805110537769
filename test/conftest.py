"""
Test fixtures; importing this module keeps every test's DDS traffic on loopback.

The environment is set before any Context exists, so in-process nodes and every subprocess
the tests start use loopback discovery in a domain of this test process's own. Tests come in
tiers by folder, each also a marker: unit (pure logic, no ROS graph), node (nodes in this
process), system (installed executables and the install tree); `pytest test/unit` or
`pytest -m unit` runs one tier.
"""

import os
from pathlib import Path
import signal

from lab_grader.domains import claim_domain
import pytest
import rclpy
from rclpy.context import Context
from ros_helpers import events_executor
from simple_robot_control.guarded_node import GuardedNode

os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
os.environ['ROS_STATIC_PEERS'] = ''
# A domain claimed for this process (each pytest-xdist worker has its own), so that neither the
# other workers nor a grade_lab running at the same time share it; held until the process ends.
DOMAIN = claim_domain()
os.environ['ROS_DOMAIN_ID'] = str(DOMAIN.domain_id)
# Peers found within about half a second rather than up to 3 s (see the file).
os.environ.setdefault('FASTRTPS_DEFAULT_PROFILES_FILE', str(
    Path(__file__).resolve().parents[1] / 'config' / 'fastdds_quick_discovery.xml'))

# A suite started in the background (`make test &`, nohup) inherits SIGINT, SIGQUIT or SIGHUP
# ignored, and every program it starts would too: the tests send signals to programs started as
# a terminal starts them, so the dispositions go back to the defaults first.
for _number in (signal.SIGINT, signal.SIGQUIT, signal.SIGHUP, signal.SIGTERM):
    if signal.getsignal(_number) == signal.SIG_IGN:
        signal.signal(_number, signal.default_int_handler if _number == signal.SIGINT
                      else signal.SIG_DFL)

TIERS = ('unit', 'node', 'system')
# What a GuardedNode logs when a callback raised what no check foresaw.
INTERNAL_ERROR = ']: internal error in '


def pytest_collection_modifyitems(items):
    """Mark each test with the tier of the folder it lives in."""
    for item in items:
        tier = Path(item.fspath).parent.name
        if tier in TIERS:
            item.add_marker(getattr(pytest.mark, tier))


@pytest.fixture
def ros_context():
    """Give the test a Context of its own, always shut down."""
    context = Context()
    rclpy.init(context=context)
    try:
        yield context
    finally:
        rclpy.try_shutdown(context=context)


@pytest.fixture
def executor(ros_context):
    """Give the test an executor in its context; destroy its nodes afterwards."""
    with events_executor(ros_context) as executor:
        yield executor


@pytest.fixture(autouse=True)
def no_internal_error(request, monkeypatch):
    """
    Fail a test whose nodes logged an internal error.

    In this process, or in the logs of the programs it started (start_logged's, in its
    tmp_path).

    A GuardedNode logs and swallows what no check foresaw, so the node carries on; a test that
    passed beside such a line would hide a bug. A test that provokes one on purpose says so with
    the mark internal_error_expected.
    """
    reported = []
    report = GuardedNode.report_internal_error

    def recorded(node, what, error):
        reported.append(f'{node.get_name()}: internal error in {what}: '
                        f'{type(error).__name__}: {error}')
        report(node, what, error)

    monkeypatch.setattr(GuardedNode, 'report_internal_error', recorded)
    yield
    folder = request.node.funcargs.get('tmp_path')
    for log in sorted(folder.rglob('*.log')) if folder is not None else ():
        reported += [f'{log.name}: {line.strip()}' for line in
                     log.read_text(errors='replace').splitlines() if INTERNAL_ERROR in line]
    if reported and request.node.get_closest_marker('internal_error_expected') is None:
        pytest.fail('a node logged an internal error: ' + '; '.join(reported[:3]),
                    pytrace=False)
