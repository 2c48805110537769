"""Runs written as bags, as the lab's recorders write them, for the tests of runs and plot_run."""

import math

import numpy as np
from rosbags.typesys import get_typestore, Stores
from simple_robot_control.bag import BagWriter

STORE = get_typestore(Stores.ROS2_JAZZY)
T = STORE.types
LATCHED = [{'history': 'keep_last', 'depth': 1, 'reliability': 'reliable',
            'durability': 'transient_local', 'deadline': {'sec': 0, 'nsec': 0},
            'lifespan': {'sec': 0, 'nsec': 0}, 'liveliness': 'automatic',
            'liveliness_lease_duration': {'sec': 0, 'nsec': 0},
            'avoid_ros_namespace_conventions': False}]


def header(seconds):
    stamp = T['builtin_interfaces/msg/Time'](sec=int(seconds),
                                             nanosec=round(seconds % 1 * 1e9))
    return T['std_msgs/msg/Header'](stamp=stamp, frame_id='map')


def pose(x, y, theta):
    return T['geometry_msgs/msg/Pose'](
        position=T['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
        orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=math.sin(theta / 2),
                                                      w=math.cos(theta / 2)))


def odometry(seconds, x):
    covariance = np.zeros(36)
    return T['nav_msgs/msg/Odometry'](
        header=header(seconds), child_frame_id='robot0/base_link',
        pose=T['geometry_msgs/msg/PoseWithCovariance'](pose=pose(x, 2.0, 0.0),
                                                       covariance=covariance),
        twist=T['geometry_msgs/msg/TwistWithCovariance'](
            twist=T['geometry_msgs/msg/Twist'](
                linear=T['geometry_msgs/msg/Vector3'](x=0.5, y=0.0, z=0.0),
                angular=T['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0)),
            covariance=covariance))


def write_run(path, steps=100, finish=True, goal_x=3.0):
    """Drive from x = 1 to 3 in steps, reporting STARTED and WAYPOINT 1 (and FINISHED)."""
    bag = BagWriter(path)
    course = bag.add_topic('/waypoints', 'nav_msgs/msg/Path', LATCHED)
    odom = bag.add_topic('/robot0/odom', 'nav_msgs/msg/Odometry', LATCHED)
    status = bag.add_topic('/robot_status', 'std_msgs/msg/String', LATCHED)

    def write(channel, time, message, kind):
        bag.write(channel, round(time * 1e9), STORE.serialize_cdr(message, kind))
    path_message = T['nav_msgs/msg/Path'](header=header(0), poses=[
        T['geometry_msgs/msg/PoseStamped'](header=header(0), pose=pose(goal_x, 2.0, 0.0))])
    write(course, 0.0, path_message, 'nav_msgs/msg/Path')
    for step in range(steps + 1):
        time, x = step * 0.02, 1.0 + 2.0 * step / steps
        write(odom, time, odometry(time, x), 'nav_msgs/msg/Odometry')
        if step == 0:
            for text in ('hello from another node', 'STARTED 1.000 2.000 0.00'):
                write(status, time, T['std_msgs/msg/String'](data=text), 'std_msgs/msg/String')
    if finish:
        for text in ('WAYPOINT 1 3.000 2.000 0.00', 'FINISHED'):
            write(status, time, T['std_msgs/msg/String'](data=text), 'std_msgs/msg/String')
    return bag
