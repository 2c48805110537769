"""A swarm's ground truth and sensors get their publishers once someone reads them."""

from nav_msgs.msg import Odometry
import pytest
from ros_helpers import overrides, simulator_and_client, spin_until
from sensor_msgs.msg import LaserScan, Range
from simple_robot_control.share import BUNDLED_ROBOT, shared_file
from stdr_lite.node.stdr_lite import StdrLite

LAB_ROBOT = shared_file(*BUNDLED_ROBOT)


def simulator_publishes(simulator, topic):
    return any(info.node_name == simulator.get_name()
               for info in simulator.get_publishers_info_by_topic(topic))


@pytest.fixture
def on_demand(ros_context, executor):
    """Give (simulator, client node): the lab robot, its optional topics made on demand."""
    return simulator_and_client(ros_context, executor, robot_description=LAB_ROBOT,
                                optional_topics='on_demand', real_time_factor=5.0)


def test_no_reader_no_publisher(on_demand, executor):
    simulator, client = on_demand
    odometry = []
    client.create_subscription(Odometry, '/robot0/odom', odometry.append, 10)
    spin_until(executor, lambda: len(odometry) > 60, what='a second of odometry')
    for topic in ('/robot0/ground_truth', '/robot0/laser_0', '/robot0/sonar_0'):
        assert not simulator_publishes(simulator, topic), topic
    assert simulator_publishes(simulator, '/robot0/odom')


def test_a_reader_gets_its_sensor_and_the_ground_truth(on_demand, executor):
    simulator, client = on_demand
    scans, truths, ranges = [], [], []
    client.create_subscription(LaserScan, '/robot0/laser_0', scans.append, 10)
    client.create_subscription(Odometry, '/robot0/ground_truth', truths.append, 10)
    spin_until(executor, lambda: scans and truths, timeout=30.0,
               what='the laser and the ground truth, made on demand')
    assert scans[-1].header.frame_id == 'robot0/laser_0'
    assert truths[-1].pose.pose.position.x == pytest.approx(1.0, abs=0.01)
    assert not simulator_publishes(simulator, '/robot0/sonar_0')
    client.create_subscription(Range, '/robot0/sonar_0', ranges.append, 10)
    spin_until(executor, lambda: ranges, timeout=30.0, what='a sonar, made on demand')


def test_auto_makes_them_at_once_for_a_few_robots(ros_context, executor):
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        robot_description=LAB_ROBOT))
    executor.add_node(simulator)
    assert simulator_publishes(simulator, '/robot0/ground_truth')
    assert simulator_publishes(simulator, '/robot0/laser_0')
