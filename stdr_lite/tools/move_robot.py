"""move_robot: the lab's interactive tool. Ask for a velocity and a duration, drive, repeat."""

import sys
import threading
import time

from nav_msgs.msg import Odometry
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.task import Future
from rclpy.time import Time
from simple_robot_control.exit_codes import EXIT_FAILED, EXIT_OK
from simple_robot_control.graph import command_type_problem, MISMATCH_PATIENCE
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import pose_from_message
from simple_robot_control.validation import ConfigError
from simple_robot_control.velocity import VelocityPublisher
from stdr_lite.tools.exact_steps import ExactSteps, SimulatorUnavailable
from stdr_lite.tools.lab_session import ask_motion, EndOfInput, format_pose
from stdr_lite.tools.parameters import MOVE_ROBOT_PARAMETERS

# Wall seconds the stop command at exit may take to be received.
STOP_DELIVERY = 0.4


DESCRIPTION = ('move_robot: drive a simulated robot by hand, as in the lab. Asks for a linear '
               'velocity (m/s), a rotational velocity (degrees/s) and a duration (s of sim '
               'time), drives, stops, prints the new pose, and repeats until end of input.')


class SimulatorSilent(Exception):
    """No odometry arrived within odom_timeout."""


class CommandsUnread(Exception):
    """The simulator reads cmd_vel as another message type than this node sends."""


class MoveRobot(GuardedNode):
    """Runs the lab dialogue in a worker thread while the executor delivers odometry."""

    def __init__(self, read_line=None, write=None, **kwargs):
        super().__init__('move_robot', **kwargs)
        params = declare_parameters(self, MOVE_ROBOT_PARAMETERS)
        self._odom_timeout = params['odom_timeout']
        self._read_line = read_line or _read_stdin_line
        self._write = write or _write_stdout
        self.finished = Future()
        self._exit_code = EXIT_OK
        self._problem = None
        self._odometry = None
        self._odometry_arrived = threading.Condition()
        self._commands = VelocityPublisher(self, f'{params["robot_name"]}/cmd_vel',
                                           params['cmd_vel_stamped'])
        self._odom_topic = self.create_subscription(
            Odometry, f'{params["robot_name"]}/odom', self._on_odometry, 10).topic_name
        self._exact_steps = ExactSteps(self, params['simulator'], self._odom_timeout)
        self._session_over = threading.Event()
        # A steady timer rather than a guard condition: EventsExecutor supports no guard
        # conditions, and the node must run on any executor.
        self.create_timer(0.05, self._finish_when_session_over,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        threading.Thread(target=self._session, daemon=True).start()

    def _on_odometry(self, message):
        with self._odometry_arrived:
            self._odometry = message
            self._odometry_arrived.notify_all()

    def _finish_when_session_over(self):
        if self._session_over.is_set() and not self.finished.done():
            if self._problem is not None:
                self.finished.set_exception(ConfigError(self._problem))
            else:
                self.finished.set_result(self._exit_code)

    def _next_odometry(self, newer_than=None):
        """Wait for odometry stamped later than newer_than (or any, if None)."""
        def fresh():
            if self._odometry is None:
                return False
            return newer_than is None or _stamp_ns(self._odometry) > _stamp_ns(newer_than)
        with self._odometry_arrived:
            if not self._odometry_arrived.wait_for(fresh, timeout=self._odom_timeout):
                raise SimulatorSilent()
            return self._odometry

    def _session(self):
        try:
            odometry = self._next_odometry()
            self._wait_for_simulator()
            stepped = self._exact_steps.connect()
            if not stepped:
                self.get_logger().info('no simulation_interfaces stepping API found: moves are '
                                       'timed by the odometry')
            while True:
                self._write(_pose_line(odometry) + '\n')
                linear, angular, duration = ask_motion(self._read_line, self._write)
                drive = self._drive_exactly if stepped else self._drive
                odometry = drive(linear, angular, duration)
        except EndOfInput:
            self._write('\n')
        except SimulatorSilent:
            self.get_logger().error(f'no odometry on {self._odom_topic} for '
                                    f'{self._odom_timeout:g} s: is stdr_lite running?')
            self._exit_code = EXIT_FAILED
        except SimulatorUnavailable as problem:
            self.get_logger().error(f'{problem}: is stdr_lite running?')
            self._exit_code = EXIT_FAILED
        except CommandsUnread as problem:
            self._problem = str(problem)
        except Exception as error:  # noqa: B902  the session's last resort
            self.report_internal_error('the session', error)
            self._exit_code = EXIT_FAILED
        finally:
            self._session_over.set()

    def _wait_for_simulator(self):
        """Wait until the simulator subscribes to our commands, so none is lost to discovery."""
        started = time.monotonic()
        deadline = started + max(self._odom_timeout, MISMATCH_PATIENCE)
        while self._commands.publisher.get_subscription_count() == 0:
            problem = command_type_problem(self, self._commands.publisher, 'cmd_vel_stamped')
            if problem is not None and time.monotonic() - started >= MISMATCH_PATIENCE:
                raise CommandsUnread(problem)
            if time.monotonic() > deadline:
                raise SimulatorSilent()
            time.sleep(0.01)

    def _drive_exactly(self, linear, angular, duration):
        """Hold the command for round(duration * rate_hz) steps; return the odometry at rest."""
        start = self._next_odometry(newer_than=self._odometry)
        steps = round(duration * self._exact_steps.rate_hz)
        if steps == 0:
            return start
        was_playing = self._exact_steps.pause()
        try:
            self._send(linear, angular)
            self._exact_steps.take(steps)
            self._send(0.0, 0.0)
        finally:
            if was_playing:
                self._exact_steps.play()
        if not was_playing:
            self._exact_steps.take(1)
        odometry = self._next_odometry(newer_than=self._odometry)
        while _is_moving(odometry):
            odometry = self._next_odometry(newer_than=odometry)
        return odometry

    def _send(self, linear, angular):
        """
        Publish a command for the simulator to take before the request that follows.

        Waiting for the acknowledgement would cost up to Fast DDS's heartbeat period (3 s);
        on one machine a sample reaches the simulator before a request sent after it, and the
        simulator takes its events in the order they arrive.
        """
        self._commands.publish(linear, angular)

    def _drive(self, linear, angular, duration):
        """
        Hold the command for duration seconds of sim time; return the odometry at rest.

        The command goes out just after a simulation step. The motion is timed from the first
        step whose odometry shows the command applied, so the simulator applies exactly
        duration * rate_hz steps even if the command is delivered late.
        """
        start = self._next_odometry(newer_than=self._odometry)
        if duration <= 0.0:
            return start
        self._commands.publish(linear, angular)
        duration_ns = round(duration * 1e9)
        started_ns = _stamp_ns(start)
        odometry = start
        if linear != 0.0 or angular != 0.0:
            while not _is_moving(odometry) and _stamp_ns(odometry) - started_ns < duration_ns:
                before_first_step = odometry
                odometry = self._next_odometry(newer_than=odometry)
            if _is_moving(odometry) and odometry is not start:
                started_ns = _stamp_ns(before_first_step)
        while _stamp_ns(odometry) < started_ns + duration_ns:
            odometry = self._next_odometry(newer_than=odometry)
        self._commands.publish(0.0, 0.0)
        odometry = self._next_odometry(newer_than=odometry)
        while _is_moving(odometry):
            odometry = self._next_odometry(newer_than=odometry)
        return odometry

    def shut_down(self) -> None:
        """Leave the robot standing still: publish a stop and wait until it is received."""
        self._commands.publish(0.0, 0.0)
        self._commands.publisher.wait_for_all_acked(Duration(seconds=STOP_DELIVERY))


def _stamp_ns(odometry):
    return Time.from_msg(odometry.header.stamp).nanoseconds


def _is_moving(odometry):
    return odometry.twist.twist.linear.x != 0.0 or odometry.twist.twist.angular.z != 0.0


def _pose_line(odometry):
    return format_pose(*pose_from_message(odometry.pose.pose))


def _read_stdin_line():
    line = sys.stdin.readline()
    if not line:
        return None
    if not sys.stdin.isatty():
        _write_stdout(line if line.endswith('\n') else line + '\n')
    return line.rstrip('\n')


def _write_stdout(text):
    sys.stdout.write(text)
    sys.stdout.flush()


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('move_robot', DESCRIPTION, MOVE_ROBOT_PARAMETERS)
    sys.exit(run('move_robot', parser, lambda options: MoveRobot(), argv))


if __name__ == '__main__':
    main()
