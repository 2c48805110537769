"""
Nodes that a bug in one callback cannot kill: the last resort behind every check.

Expected problems (bad input, refusals) are handled where they arise, each with its own line.
What no check foresaw must still not end the node: every subscription, timer and service
callback of a GuardedNode runs inside a guard that turns an unexpected exception into one
logged line naming the callback, the exception and where it was raised, and lets the node carry
on. A guarded service answers with its response's defaults, unless given a failure answer.

A node whose construction fails (a bad parameter, a file that cannot be read) destroys what it
made of itself before the error goes on: left to the garbage collector, its DDS entities would
be destroyed at any later allocation, holding the GIL, and Fast DDS can then wait forever on
an event thread that itself waits for the GIL (seen in the suite: a test process hung in
rcl_node_fini called from an import).
"""

from collections.abc import Callable
import functools
import os
import time
import traceback

from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.service import Service
from rclpy.subscription import Subscription
from rclpy.timer import Timer

# An error repeated by the same callback is logged at most this often (wall seconds).
REPEAT_AFTER = 5.0
MESSAGE_LENGTH = 200


class GuardedNode(Node):
    """An rclpy Node whose callbacks are guarded (see the module's docstring)."""

    def __init__(self, *args, **kwargs):
        self._reported_at = {}
        self._node_made = False
        super().__init__(*args, **kwargs)
        self._node_made = True

    def __init_subclass__(cls, **kwargs):
        """Make a subclass's __init__ destroy the node it made if it raises."""
        super().__init_subclass__(**kwargs)
        if '__init__' in cls.__dict__:
            cls.__init__ = _destroyed_if_it_raises(cls.__dict__['__init__'])

    def guard(self, callback: Callable, what: str, failure: Callable | None = None) -> Callable:
        """
        Return callback guarded: an exception is reported, and failure(*args) answered instead.

        failure defaults to returning None; for a service it gives the response to send. The
        guarded callback has callback's signature, as rclpy reads it (a subscription's callback
        may take the message info too).
        """
        @functools.wraps(callback)
        def guarded(*args):
            try:
                return callback(*args)
            except Exception as error:  # noqa: B902  the last resort, by design
                self.report_internal_error(what, error)
                return None if failure is None else failure(*args)
        return guarded

    def report_internal_error(self, what: str, error: Exception) -> None:
        """Log one line about an exception nothing expected, at most every REPEAT_AFTER s."""
        now = time.monotonic()
        if now - self._reported_at.get(what, -REPEAT_AFTER) < REPEAT_AFTER:
            return
        self._reported_at[what] = now
        frames = traceback.extract_tb(error.__traceback__)
        where = (f' at {os.path.basename(frames[-1].filename)}:{frames[-1].lineno}'
                 if frames else '')
        text = ' '.join(str(error).split())
        if len(text) > MESSAGE_LENGTH:
            text = text[:MESSAGE_LENGTH] + '...'
        self.get_logger().error(f'internal error in {what}: {type(error).__name__}: {text}'
                                f'{where}; the node carries on (please report this)')

    def create_subscription(self, msg_type: type, topic: str, callback: Callable,
                            qos_profile: QoSProfile | int, **kwargs) -> Subscription:
        return super().create_subscription(
            msg_type, topic, self.guard(callback, f'the subscription to {topic}'), qos_profile,
            **kwargs)

    def create_timer(self, timer_period_sec: float, callback: Callable, *args,
                     **kwargs) -> Timer:
        name = getattr(callback, '__qualname__', type(callback).__name__)
        return super().create_timer(timer_period_sec, self.guard(callback, f'the timer {name}'),
                                    *args, **kwargs)

    def create_service(self, srv_type: type, srv_name: str, callback: Callable, *,
                       failure: Callable | None = None, **kwargs) -> Service:
        """Create a service; failure(request, response) answers when callback raises."""
        return super().create_service(
            srv_type, srv_name, self.guard(callback, f'the service {srv_name}',
                                           failure or (lambda request, response: response)),
            **kwargs)


def _destroyed_if_it_raises(init):
    """
    Wrap a node's __init__: on an error once rclpy's Node is made, destroy it, then raise.

    An interruption (a signal while starting: BaseException) leaves everything as it is, for
    the program ends at once and rclpy may be half way through its own start.
    """
    @functools.wraps(init)
    def constructed(node, *args, **kwargs):
        try:
            init(node, *args, **kwargs)
        except Exception:
            # Node's own destroy_node (a subclass's may need what was never made); a second
            # call, by an enclosing subclass's __init__, does nothing.
            if getattr(node, '_node_made', False):
                Node.destroy_node(node)
            raise
    return constructed
