"""
Test fixtures; importing this module keeps every test's DDS traffic on loopback.

The environment is set before any Context exists, so in-process nodes and every subprocess
the tests start use loopback discovery in a domain of this test session's own.
"""

import os
import random

import pytest
import rclpy
from rclpy.context import Context
from ros_helpers import events_executor

os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
os.environ['ROS_STATIC_PEERS'] = ''
os.environ['ROS_DOMAIN_ID'] = str(random.SystemRandom().randint(1, 100))


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
