"""record_run writes a running simulation into a bag that an independent reader reads back."""

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from ros_helpers import simulator_and_client, spin_until
from rosbags.highlevel import AnyReader
from std_msgs.msg import String
from waypoint_lab.record_run import RunRecorder

LATCHED = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def test_a_run_is_recorded_in_order_with_its_qos(ros_context, executor, tmp_path):
    _, client = simulator_and_client(ros_context, executor, real_time_factor=5.0)
    status = client.create_publisher(String, '/robot_status', LATCHED)
    status.publish(String(data='STARTED 1.000 2.000 0.00'))
    recorder = RunRecorder(bag=str(tmp_path / 'run.mcap'), context=ros_context)
    executor.add_node(recorder)
    wanted = {'/robot_status', '/robot0/odom', '/tf', '/tf_static', '/map'}
    spin_until(executor, lambda: wanted <= set(recorder.recording.topics), timeout=20.0,
               what='every topic of the run subscribed')
    spin_until(executor, lambda: recorder.recording.bag.message_count > 200, timeout=20.0,
               what='a few seconds of the run')
    status.publish(String(data='FINISHED'))
    spin_until(executor, lambda: recorder.recording.bag.message_count > 400, timeout=20.0,
               what='more of the run')
    recorder.shut_down()
    with AnyReader([tmp_path / 'run.mcap']) as reader:
        by_topic = {connection.topic: connection for connection in reader.connections}
        assert by_topic['/tf_static'].ext.offered_qos_profiles[0].durability.name == (
            'TRANSIENT_LOCAL')
        assert by_topic['/robot0/odom'].msgtype == 'nav_msgs/msg/Odometry'
        texts = [reader.deserialize(data, 'std_msgs/msg/String').data
                 for _, _, data in reader.messages([by_topic['/robot_status']])]
        stamps = [reader.deserialize(data, 'nav_msgs/msg/Odometry').header.stamp
                  for _, _, data in reader.messages([by_topic['/robot0/odom']])]
    assert texts == ['STARTED 1.000 2.000 0.00', 'FINISHED']
    times = [stamp.sec * 10 ** 9 + stamp.nanosec for stamp in stamps]
    assert len(times) > 50 and times == sorted(times)
