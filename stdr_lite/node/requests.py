"""
The simulation services' requests, served in order and in slices that keep the loop going.

Each service of the simulation API hands its callback to a RequestQueue as a job: a function
of (request, response) that fills the response and returns a note for its result, or raises
Refusal. A job with long work to do is a generator instead: it yields wherever it may pause
(between two steps, two files) and returns its note at the end; it yields WAIT while it has
nothing to do until later (a map loads in a thread of its own), which ends its slice at once.
Jobs run in the order their requests came, for at most SLICE of wall time per turn of the
executor, so the simulation steps and every topic is served between slices, and the answer
goes out when the job ends. A request whose job is not done holds back the requests
after it, never the simulation. Any other exception a job raises is a bug: it is logged and
answered RESULT_OPERATION_FAILED, and the simulator carries on.

rclpy answers a service with what its callback returns, and takes every request waiting on a
service in one go; so the callback only queues the job and returns it, and the services are of
a subclass of rclpy's Service (_AnsweredLater) whose send_response, given a job and the
request's header by the executor, sends the answer once the job is done. (rclpy's own way, a
coroutine callback, is not awaited by rclpy 7.1's EventsExecutor, which the intake needs:
test/node/test_rclpy_limits.py fails once it is.)

Taking a request costs rclpy about 2 us per element of its sequences, before any check of
ours: 0.2 s for a hull of 100,000 points, 0.1 s for 50 hulls of 1000 taken in one go. So the
services live on a node of their own (<simulator>_requests), spun in a thread of its own (by
an EventsExecutor, which takes requests in the order they came, across services) that only
takes requests and queues their jobs: Python lets the simulator's thread run between the
conversion's bytecodes, so /clock keeps its pace, and every job still runs in the simulator's
thread, between its steps.
"""

from collections import deque
from collections.abc import Callable
import concurrent.futures
import contextlib
import io
import sys
import threading
import time
from types import GeneratorType

from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.service import Service
from rclpy.type_support import check_is_valid_srv_type
from simple_robot_control.guarded_node import GuardedNode
from simulation_interfaces.msg import Result
from stdr_lite.node.results import Refusal, result, SERVICE_QOS

# Wall seconds a turn of the queue may take before the executor gets its turn again.
SLICE = 0.004
PUMP_PERIOD = 0.001
# How often the simulator's thread looks for jobs the intake thread has queued, when idle.
POLL_PERIOD = 0.005
# How long the intake thread waits for a request before it looks whether it should end.
INTAKE_WAIT = 0.1
# What a job yields while it waits for work done elsewhere.
WAIT = 'wait'


def in_thread(function: Callable, *args) -> concurrent.futures.Future:
    """
    Run function(*args) in a thread of its own; return a concurrent.futures.Future of it.

    For pure computation only (numpy and scipy let the loop run meanwhile): nothing of ROS and
    nothing of the running simulation may be touched there. The thread does not hold the
    process open at exit.
    """
    future = concurrent.futures.Future()

    def work():
        try:
            future.set_result(function(*args))
        except BaseException as error:  # noqa: B902  handed to whoever waits on the future
            future.set_exception(error)
    threading.Thread(target=work, name='stdr_lite work', daemon=True).start()
    return future


def _events_executor(context):
    """
    Return rclpy's EventsExecutor in context.

    It enables faulthandler on sys.stderr, which needs a file: a captured stderr (a test's)
    has none, and the real one stands in while it is made.
    """
    try:
        return EventsExecutor(context=context)
    except io.UnsupportedOperation:
        with contextlib.redirect_stderr(sys.__stderr__):
            return EventsExecutor(context=context)


class _Job:
    """One request being served: its work, its response, and where to send the answer."""

    def __init__(self, work, request, response, report):
        self._work, self._request, self.response = work, request, response
        self._report = report
        self._steps = self._header = self._send = None
        self.done = False
        # The header comes in the intake thread, the end of the work in the simulator's.
        self._lock = threading.Lock()

    def run(self, deadline):
        """Work until the job is done or the deadline has passed; return whether it is done."""
        try:
            if self._steps is None:
                outcome = self._work(self._request, self.response)
                if not isinstance(outcome, GeneratorType):
                    return self._finish(Result.RESULT_OK, outcome)
                self._steps = outcome
            while True:
                if next(self._steps) is WAIT or time.monotonic() >= deadline:
                    return False
        except StopIteration as end:
            return self._finish(Result.RESULT_OK, end.value)
        except Refusal as refusal:
            return self._finish(refusal.code, str(refusal))
        except Exception as error:  # noqa: B902  the last resort, by design
            self._report(error)
            return self._finish(Result.RESULT_OPERATION_FAILED,
                                f'internal error: {type(error).__name__}: {error}')

    def abandon(self, reason: str) -> None:
        """End the job unfinished (the simulator is going), answering with reason."""
        if self._steps is not None:
            self._steps.close()
        self._finish(Result.RESULT_OPERATION_FAILED, reason)

    def answer_when_done(self, header, send):
        """Take the request's header: send(response, header) answers it once the job is done."""
        with self._lock:
            self._header, self._send = header, send
        self._answer()

    def _finish(self, code, message):
        if hasattr(self.response, 'result'):
            self.response.result = result(code, message or '')
        with self._lock:
            self.done = True
        self._answer()
        return True

    def _answer(self):
        with self._lock:
            if not (self.done and self._header is not None):
                return
            header, self._header = self._header, None
        self._send(self.response, header)


class _AnsweredLater(Service):
    """A service whose callback returns a _Job: the answer goes out when the job is done."""

    def send_response(self, response, header):
        if isinstance(response, _Job):
            response.answer_when_done(header, super().send_response)
        else:
            super().send_response(response, header)


class _Intake(GuardedNode):
    """The node that takes the simulation services' requests, in a thread of its own."""

    def create_service_answered_later(self, kind, name, take):
        """Do what Node.create_service does, with a service of the _AnsweredLater kind."""
        check_is_valid_srv_type(kind)
        with self.handle:
            handle = rclpy_implementation.Service(self.handle, kind, name,
                                                  SERVICE_QOS.get_c_qos_profile())
        service = _AnsweredLater(handle, kind, name, take, self.default_callback_group,
                                 SERVICE_QOS)
        self.default_callback_group.add_entity(service)
        self._services.append(service)
        self._wake_executor()
        return service


class RequestQueue:
    """Serves services whose callbacks are jobs, in order, a slice at a time."""

    def __init__(self, node):
        self._node = node
        self._jobs = deque()
        self._pump = node.create_timer(PUMP_PERIOD, self._run_jobs,
                                       clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._pump.cancel()
        node.create_timer(POLL_PERIOD, self._look_for_jobs,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        # Named by a local remapping, which comes before a global __node:= of the simulator's.
        self._intake = _Intake(
            'requests', context=node.context, namespace=node.get_namespace(),
            cli_args=['--ros-args', '-r', f'__node:={node.get_name()}_requests'],
            start_parameter_services=False, enable_rosout=False)
        self._closing = threading.Event()
        self._thread = threading.Thread(target=self._take_requests, name='stdr_lite requests',
                                        daemon=True)
        self._thread.start()

    @property
    def busy(self) -> bool:
        """Whether some request is still being served."""
        return bool(self._jobs)

    def serve(self, kind: type, name: str, work: Callable, private: bool = True) -> Service:
        """Serve the service ~/name (name, unless private) of type kind with work as a job."""
        def take(request, response):
            # In the intake thread: the job waits for the simulator's thread to run it.
            job = _Job(work, request, response, report)
            self._jobs.append(job)
            return job

        def report(error):
            self._node.report_internal_error(f'the service {name}', error)
        full_name = f'{self._node.get_fully_qualified_name()}/{name}' if private else name
        return self._intake.create_service_answered_later(kind, full_name, take)

    def close(self) -> None:
        """Stop taking requests and let the intake node go (before the simulator's node)."""
        self._closing.set()
        self._thread.join(timeout=2 * INTAKE_WAIT + 1.0)
        self._intake.destroy_node()

    def _take_requests(self):
        # Events are taken in the order they came, across services, as the jobs must run.
        executor = _events_executor(self._node.context)
        executor.add_node(self._intake)
        try:
            while not self._closing.is_set() and self._node.context.ok():
                executor.spin_once(timeout_sec=INTAKE_WAIT)
        except ExternalShutdownException:
            pass

    def _look_for_jobs(self):
        if self._jobs and self._pump.is_canceled():
            self._pump.reset()

    def abandon(self, reason: str) -> None:
        """Answer every request not yet served with a failure: the simulator is going."""
        while self._jobs:
            self._jobs.popleft().abandon(reason)

    def _run_jobs(self):
        deadline = time.monotonic() + SLICE
        while self._jobs:
            if not self._jobs[0].run(deadline):
                return
            self._jobs.popleft()
            if time.monotonic() >= deadline:
                return
        self._pump.cancel()
