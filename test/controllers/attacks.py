"""
Submissions that try to buy a verdict without driving, written for grade_lab's tests.

    python3 attacks.py @ WAYPOINT_FILE     (the attack: the first word of ./behaviour)

teleport asks the simulator to put the robot on each goal (set_entity_state, then initialpose),
then reports the goals; fake_truth publishes its own ground truth, odometry and clock, at the
goal, and reports what it published; snoop prints everything its environment and its
ancestors' and the simulator's command lines say, then reports honestly; tamper also writes
into the course folder the behaviour file names (changes a course, plants one); escape leaves
a daemon started with env -i in a session of its own, and prints its pid; kill_simulator ends
the simulator (found through the graph: the pid in its publisher's DDS id); flood sends
a thousand robot_status messages; hog allocates 8 GB. As root's grade_lab would meet them:
kill_reaper kills its parent and pid 1, then escapes; status_pipe writes `started 1` and
`exit 0` into every pipe it holds, then escapes; fill_disk writes into its home until the
disk is full; intrude commands robot0 backwards in the first ten ROS domains (another course's
among them, were it reachable) while it reports; honest runs waypoint_controller. Each prints
what it did.
"""

import math
import os
from pathlib import Path
import signal
import stat
import subprocess
import sys
import time

from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
import rclpy
from rclpy.duration import Duration
from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from simulation_interfaces.srv import GetCurrentWorld, SetEntityState
from std_msgs.msg import String


def say(text):
    print(f'attack: {text}', flush=True)


def read_waypoints(path):
    numbers = [float(word) for line in Path(path).read_text().splitlines()
               for word in line.split('#')[0].split()]
    return [(x, y, math.radians(theta))
            for x, y, theta in zip(numbers[0::3], numbers[1::3], numbers[2::3])]


def status_text(kind, pose):
    x, y, theta = pose
    return f'{kind} {x:.3f} {y:.3f} {math.degrees(theta):.2f}'


def spin_for(node, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.02)


class Attacker(Node):

    def __init__(self):
        super().__init__('attacker')
        # Deep enough to hold a whole flood: publishing never waits for the grader's acks.
        self.status = self.create_publisher(String, 'robot_status', 1000)
        self.poses = []
        self.create_subscription(Odometry, 'robot0/odom',
                                 lambda message: self.poses.append(pose_of(message)), 10)

    def report(self, text):
        self.status.publish(String(data=text))

    def wait_for_odometry(self):
        while not self.poses:
            rclpy.spin_once(self, timeout_sec=0.1)


def pose_of(odometry):
    orientation = odometry.pose.pose.orientation
    theta = 2.0 * math.atan2(orientation.z, orientation.w)
    return odometry.pose.pose.position.x, odometry.pose.pose.position.y, theta


def teleport(node, goals):
    client = node.create_client(SetEntityState, '/stdr_lite/set_entity_state')
    offered = client.wait_for_service(timeout_sec=3.0)
    say(f'set_entity_state {"offered" if offered else "not offered"}')
    mover = node.create_publisher(PoseWithCovarianceStamped, 'robot0/initialpose', 10)
    for number, goal in enumerate(goals, start=1):
        request = SetEntityState.Request(entity='robot0')
        request.state.pose.position.x, request.state.pose.position.y = goal[0], goal[1]
        request.state.pose.orientation.z = math.sin(goal[2] / 2.0)
        request.state.pose.orientation.w = math.cos(goal[2] / 2.0)
        if offered:
            future = client.call_async(request)
            rclpy.spin_until_future_complete(node, future, timeout_sec=3.0)
        message = PoseWithCovarianceStamped()
        message.header.frame_id = 'map'
        message.pose.pose = request.state.pose
        mover.publish(message)
        spin_for(node, 0.5)
        say(f'odometry after the move: {node.poses[-1]}')
        node.report(status_text(f'WAYPOINT {number}', goal))
    node.report('FINISHED')


def fake_truth(node, goals):
    truth = node.create_publisher(Odometry, 'robot0/ground_truth', 10)
    odometry = node.create_publisher(Odometry, 'robot0/odom', 10)
    clock = node.create_publisher(Clock, '/clock', 10)
    for number, goal in enumerate(goals, start=1):
        for _ in range(20):
            message = Odometry()
            message.header.frame_id = 'map'
            message.header.stamp.sec = 10_000 + number
            message.pose.pose.position.x, message.pose.pose.position.y = goal[0], goal[1]
            message.pose.pose.orientation.z = math.sin(goal[2] / 2.0)
            message.pose.pose.orientation.w = math.cos(goal[2] / 2.0)
            truth.publish(message)
            odometry.publish(message)
            clock.publish(Clock(clock=message.header.stamp))
            spin_for(node, 0.02)
        node.report(status_text(f'WAYPOINT {number}', goal))
    node.report('FINISHED')
    say('published ground truth, odometry and clock at every goal')


def snoop():
    """Print what the environment and the command lines around the submission name."""
    seen = [f'environment: {" ".join(f"{k}={v}" for k, v in os.environ.items())}']
    pid = os.getppid()
    while pid > 1:
        seen.append(f'ancestor {pid}: {cmdline(pid)}')
        pid = parent_of(pid)
    for entry in os.listdir('/proc'):
        if entry.isdigit() and 'stdr_lite' in cmdline(int(entry)):
            seen.append(f'simulator {entry}: {cmdline(int(entry))}')
    for entry in os.listdir('/proc'):
        if entry.isdigit():
            for name in ('environ', 'cwd'):
                try:
                    path = Path(f'/proc/{entry}/{name}')
                    text = os.readlink(path) if name == 'cwd' else path.read_bytes().decode()
                    seen.append(f'{name} of {entry}: {text}')
                except OSError:
                    continue
    for line in seen:
        say(f'snooped {line}')


def cmdline(pid):
    try:
        return Path(f'/proc/{pid}/cmdline').read_bytes().replace(b'\0', b' ').decode()
    except OSError:
        return ''


def parent_of(pid):
    try:
        return int(Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()[1])
    except (OSError, ValueError, IndexError):
        return 0


def current_world(node):
    client = node.create_client(GetCurrentWorld, '/stdr_lite/get_current_world')
    if client.wait_for_service(timeout_sec=3.0):
        future = client.call_async(GetCurrentWorld.Request())
        rclpy.spin_until_future_complete(node, future, timeout_sec=3.0)
        if future.result() is not None:
            world = future.result().world
            say(f'snooped current world {world.name} at {world.world_resource.uri!r}')


def tamper(folder):
    folder = Path(folder)
    try:
        for course in sorted(folder.glob('*.txt')):
            course.write_text('9.0 9.0 0.0\n')
            say(f'rewrote {course}')
        (folder / 'planted.txt').write_text('1.0 2.0 0.0\n')
        say(f'planted {folder / "planted.txt"}')
    except OSError as error:
        say(f'could not write into the courses: {error.strerror}')


def kill_reaper():
    for pid in (os.getppid(), 1):
        try:
            os.kill(pid, signal.SIGKILL)
            say(f'killed pid {pid}')
        except OSError as error:
            say(f'could not kill pid {pid}: {error.strerror}')


def status_pipe():
    written = 0
    for descriptor in range(3, 256):
        try:
            if stat.S_ISFIFO(os.fstat(descriptor).st_mode):
                os.write(descriptor, b'started 1\nexit 0\n')
                written += 1
        except OSError:
            continue
    say(f'wrote into {written} pipes')


def fill_disk():
    written = 0
    try:
        with open(Path.home() / 'filler', 'wb') as filler:
            while True:
                filler.write(bytes(1 << 20))
                filler.flush()
                written += 1
    except OSError as error:
        say(f'disk full after {written} MB: {error.strerror}')


def intrude(node, goals):
    """Command robot0 backwards in domains 0 to 9 while reporting this course's goals."""
    from geometry_msgs.msg import Twist
    publishers = []
    for domain in range(10):
        context = rclpy.Context()
        rclpy.init(context=context, domain_id=domain)
        other = rclpy.create_node('intruder', context=context)
        publishers.append(other.create_publisher(Twist, '/robot0/cmd_vel', 10))
    say('commanding robot0 in domains 0 to 9')
    backwards = Twist()
    backwards.linear.x = -0.5
    for _ in range(100):
        for publisher in publishers:
            publisher.publish(backwards)
        spin_for(node, 0.05)
    for number, _ in enumerate(goals, start=1):
        node.report(status_text(f'WAYPOINT {number}', node.poses[-1]))
    node.report('FINISHED')


def escape():
    daemon = subprocess.Popen(
        ['env', '-i', sys.executable, '-c',
         'import signal\n'
         'signal.signal(signal.SIGINT, signal.SIG_IGN)\n'
         'signal.pause()\n'],
        start_new_session=True, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL)
    say(f'daemon pid {daemon.pid}')


def kill_simulator(node):
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline:
        publishers = node.get_publishers_info_by_topic('/clock')
        publishers += node.get_publishers_info_by_topic('/robot0/odom')
        for info in publishers:
            gid = bytes(info.endpoint_gid)
            if info.node_name != 'stdr_lite':
                continue
            bits = int.from_bytes(gid[4:6], 'little')
            for entry in os.listdir('/proc'):
                if entry.isdigit() and int(entry) & 0xFFFF == bits and (
                        'stdr_lite' in cmdline(int(entry))):
                    os.kill(int(entry), signal.SIGKILL)
                    say(f'killed the simulator, pid {entry}')
                    return
        spin_for(node, 0.1)
    say('found no simulator to kill')


def flood(node, goals):
    # Heard, or a flood would be no attack: the grader's subscription matched first.
    deadline = time.monotonic() + 30.0
    while node.status.get_subscription_count() == 0 and time.monotonic() < deadline:
        spin_for(node, 0.05)
    for _ in range(1000):
        node.report(status_text('WAYPOINT 1', goals[0]))
    # The last of them delivered before this process ends, however loaded the machine.
    node.status.wait_for_all_acked(Duration(seconds=30))
    say('sent 1000 statuses')


def main(waypoint_file):
    words = Path('behaviour').read_text().split()
    attack, argument = words[0], (words[1:] or [''])[0]
    if attack == 'honest':
        controller = os.path.join(os.path.dirname(sys.executable), 'waypoint_controller')
        os.execv(controller, [controller, waypoint_file])
    if attack == 'fill_disk':
        fill_disk()
    if attack == 'hog':
        say('allocating 8 GB')
        hoard = bytearray(8 << 30)
        say(f'allocated {len(hoard)} bytes')
    goals = read_waypoints(waypoint_file)
    rclpy.init()
    node = Attacker()
    node.wait_for_odometry()
    node.report(status_text('STARTED', node.poses[-1]))
    if attack == 'teleport':
        teleport(node, goals)
    elif attack == 'fake_truth':
        fake_truth(node, goals)
    elif attack == 'kill_simulator':
        kill_simulator(node)
    elif attack == 'flood':
        flood(node, goals)
    elif attack == 'intrude':
        intrude(node, goals)
    else:
        if attack in ('snoop', 'tamper'):
            snoop()
            current_world(node)
        if attack == 'tamper':
            tamper(argument)
        if attack == 'kill_reaper':
            kill_reaper()
        if attack == 'status_pipe':
            status_pipe()
        if attack in ('escape', 'kill_reaper', 'status_pipe'):
            escape()
        for number, _ in enumerate(goals, start=1):
            node.report(status_text(f'WAYPOINT {number}', node.poses[-1]))
        node.report('FINISHED')
    spin_for(node, 0.5)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == '__main__':
    main(sys.argv[2])
