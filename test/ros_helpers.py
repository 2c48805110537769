"""Spinning helpers for in-process tests: every wait has a deadline."""

from contextlib import contextmanager
import time

from geometry_msgs.msg import PoseStamped
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from simple_robot_control.pose import set_pose
from stdr_lite.node.stdr_lite import StdrLite


def spin_until(executor, condition, timeout=10.0, what='condition'):
    """Spin executor until condition() is true; fail the test after timeout wall seconds."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f'timed out after {timeout} s waiting for {what}'
        executor.spin_once(timeout_sec=0.01)


def spin_for(executor, seconds):
    """Spin executor for seconds of wall time, whatever happens."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.01)


def overrides(**values):
    """Parameter overrides for a node's constructor."""
    return [Parameter(name, value=value) for name, value in values.items()]


def simulator_and_client(ros_context, executor, **parameters):
    """Give (stdr_lite with these parameters, a client node), both in the executor."""
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(**parameters))
    client = Node('client', context=ros_context)
    for node in (simulator, client):
        executor.add_node(node)
    return simulator, client


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


SERVICE_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)


class ServiceCaller:
    """Calls a node's services by short name (get_entities -> /stdr_lite/get_entities)."""

    def __init__(self, executor, node, prefix='/stdr_lite'):
        self._executor, self._node, self._prefix = executor, node, prefix
        self._clients = {}

    def client(self, kind, name):
        if name not in self._clients:
            client = self._node.create_client(kind, f'{self._prefix}/{name}',
                                              qos_profile=SERVICE_QOS)
            spin_until(self._executor, client.service_is_ready, what=f'service {name}')
            self._clients[name] = client
        return self._clients[name]

    def __call__(self, kind, service, /, timeout=10.0, **fields):
        """Call and return the response; fields fill the request."""
        future = self.client(kind, service).call_async(kind.Request(**fields))
        spin_until(self._executor, future.done, timeout, f'the answer of {service}')
        return future.result()


def pose_stamped(x, y, theta=0.0, frame_id=''):
    """Return a geometry_msgs/PoseStamped at the planar pose, as spawn requests take it."""
    message = PoseStamped()
    message.header.frame_id = frame_id
    set_pose(message.pose, x, y, theta)
    return message
