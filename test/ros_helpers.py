"""Spinning helpers for in-process tests: every wait has a deadline."""

from contextlib import contextmanager
import time

from rclpy.experimental import EventsExecutor
from rclpy.parameter import Parameter


def spin_until(executor, condition, timeout=10.0, what='condition'):
    """Spin executor until condition() is true; fail the test after timeout wall seconds."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f'timed out after {timeout} s waiting for {what}'
        executor.spin_once(timeout_sec=0.01)


def overrides(**values):
    """Parameter overrides for a node's constructor."""
    return [Parameter(name, value=value) for name, value in values.items()]


def wait_for_subscribers(executor, publisher, timeout=10.0):
    spin_until(executor, lambda: publisher.get_subscription_count() > 0, timeout,
               f'a subscriber on {publisher.topic_name}')


@contextmanager
def events_executor(context):
    """
    Give an EventsExecutor in context; destroy its nodes and shut it down afterwards.

    An EventsExecutor may still deliver events queued for a node it no longer holds, so each
    run of nodes gets an executor of its own.
    """
    executor = EventsExecutor(context=context)
    try:
        yield executor
    finally:
        for node in executor.get_nodes():
            executor.remove_node(node)
            node.destroy_node()
        executor.shutdown()
