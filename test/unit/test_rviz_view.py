"""The bundled RViz view looks at what stdr_lite publishes, with the QoS it publishes with."""

from pathlib import Path

from stdr_lite.node.parameters import PARAMETERS
import yaml

VIEW = yaml.safe_load((Path(__file__).resolve().parents[2] / 'rviz' / 'stdr_lite.rviz')
                      .read_text())['Visualization Manager']
DEFAULTS = {spec.name: spec.default for spec in PARAMETERS}


def displays(kind):
    return [display for display in VIEW['Displays']
            if display['Class'] == f'rviz_default_plugins/{kind}']


def test_fixed_frame_is_the_map_frame():
    assert VIEW['Global Options']['Fixed Frame'] == DEFAULTS['map_frame_id']


def test_latched_topics_are_asked_for_as_latched():
    for display in displays('Map') + displays('MarkerArray'):
        assert display['Topic']['Durability Policy'] == 'Transient Local'
        assert display['Topic']['Reliability Policy'] == 'Reliable'
    assert [display['Topic']['Value'] for display in displays('Map')] == ['/map']
    assert [display['Topic']['Value'] for display in displays('MarkerArray')] == [
        '/stdr_lite/robot_markers']


def test_robot0s_sensors_odometry_and_pose_tool_are_shown():
    assert [display['Topic']['Value'] for display in displays('LaserScan')] == ['/robot0/laser_0']
    assert [display['Topic']['Value'] for display in displays('Range')] == [
        f'/robot0/sonar_{index}' for index in range(5)]
    assert [display['Topic']['Value'] for display in displays('Odometry')] == ['/robot0/odom']
    tools = {tool['Class']: tool for tool in VIEW['Tools']}
    assert tools['rviz_default_plugins/SetInitialPose']['Topic']['Value'] == '/robot0/initialpose'
