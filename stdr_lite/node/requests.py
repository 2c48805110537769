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
service in one go; so the callback only queues the job, and the answer goes out later through
the service's own send_response, with the request's header, which the queue takes where the
executor hands it over.
"""

from collections import deque
import concurrent.futures
import threading
import time
from types import GeneratorType

from rclpy.clock import Clock, ClockType
from simulation_interfaces.msg import Result
from stdr_lite.node.answers import Refusal, result, SERVICE_QOS

# Wall seconds a turn of the queue may take before the executor gets its turn again.
SLICE = 0.004
PUMP_PERIOD = 0.001
# What a job yields while it waits for work done elsewhere.
WAIT = 'wait'


def in_thread(function, *args):
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


class _Job:
    """One request being served: its work, its response, and where to send the answer."""

    def __init__(self, work, request, response, send, report):
        self._work, self._request, self.response = work, request, response
        self._send, self._report = send, report
        self._steps = self._header = None
        self.done = False

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

    def abandon(self, reason):
        """End the job unfinished (the simulator is going), answering with reason."""
        if self._steps is not None:
            self._steps.close()
        self._finish(Result.RESULT_OPERATION_FAILED, reason)

    def answer_when_done(self, header):
        """Take the request's header: the answer goes to it once the job is done."""
        self._header = header
        self._answer()

    def _finish(self, code, message):
        if hasattr(self.response, 'result'):
            self.response.result = result(code, message or '')
        self.done = True
        self._answer()
        return True

    def _answer(self):
        if self.done and self._header is not None:
            header, self._header = self._header, None
            self._send(self.response, header)


class RequestQueue:
    """Serves services whose callbacks are jobs, in order, a slice at a time."""

    def __init__(self, node):
        self._node = node
        self._jobs = deque()
        self._pump = node.create_timer(PUMP_PERIOD, self._run_jobs,
                                       clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._pump.cancel()

    @property
    def busy(self):
        """Whether some request is still being served."""
        return bool(self._jobs)

    def serve(self, kind, name, work, private=True):
        """Serve the service ~/name (name, unless private) of type kind with work as a job."""
        def take(request, response):
            # The executor takes every request waiting on a service in one go: a job run here
            # would run with all of them, before any step. Jobs wait for the pump instead.
            job = _Job(work, request, response, send_now, report)
            self._jobs.append(job)
            if self._pump.is_canceled():
                self._pump.reset()
            return job

        def report(error):
            self._node.report_internal_error(f'the service {name}', error)

        def send_response(response, header):
            if isinstance(response, _Job):
                response.answer_when_done(header)
            else:
                send_now(response, header)
        service = self._node.create_service(kind, f'~/{name}' if private else name, take,
                                            qos_profile=SERVICE_QOS)
        send_now = service.send_response
        service.send_response = send_response
        return service

    def abandon(self, reason):
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
