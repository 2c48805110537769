"""
The lab's scene as a Foxglove layout, built with Foxglove's own layout types (foxglove-sdk).

The bundled file config/foxglove_lab_layout.json is what this prints (a test keeps them equal):
the 3D panel on the map frame with the map, the course, the robot's lasers and the simulator's
markers; robot_status as it comes; the Teleop panel driving the robot through its cmd_vel; and
its sonars' ranges plotted (the 3D panel draws no sensor_msgs/Range). Foxglove imports it in
one step (Layouts, Import from file).

    python -m waypoint_lab.foxglove_layout > config/foxglove_lab_layout.json
"""

import json

import foxglove.layouts as fl
from waypoint_lab.course import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.interface import COURSE_PARAMETERS

ROBOT = next(spec.default for spec in COURSE_PARAMETERS if spec.name == 'robot_name')
# The sensors of the lab's robot, as robots/lab_robot.yaml mounts them (a test checks).
LASERS = ('laser_0',)
SONARS = tuple(f'sonar_{index}' for index in range(5))


def lab_layout(robot: str = ROBOT) -> fl.Layout:
    """Return the layout of the lab's run of robot, a lab robot (robots/lab_robot.yaml)."""
    lasers = {f'/{robot}/{laser}': fl.BaseRendererLaserScanTopicSettings(visible=True)
              for laser in LASERS}
    scene = fl.ThreeDeePanel(title='The lab room', config=fl.ThreeDeeConfig(
        follow_tf='map', topics={
            '/map': fl.BaseRendererRosOccupancyGridTopicSettings(visible=True),
            f'/{COURSE_TOPIC}': fl.BaseRendererPosesTopicSettings(visible=True),
            **lasers,
            '/stdr_lite/robot_markers': fl.BaseRendererRosMarkerTopicSettings(visible=True),
            '/stdr_lite/obstacle_markers': fl.BaseRendererRosMarkerTopicSettings(visible=True),
        }))
    status = fl.RawMessagesPanel(title=STATUS_TOPIC, config=fl.RawMessagesConfig(
        topic_path=f'/{STATUS_TOPIC}.data'))
    teleop = fl.TeleopPanel(title=f'Drive {robot}', config=fl.TeleopConfig(
        topic=f'/{robot}/cmd_vel', publish_rate=10.0))
    plot = fl.PlotPanel(title=f'{robot} sonars (m)', config=fl.PlotConfig(paths=[
        fl.PlotSeries(value=f'/{robot}/{sonar}.range', label=sonar) for sonar in SONARS]))
    side = fl.SplitContainer(direction='column', items=[
        fl.SplitItem(content=status), fl.SplitItem(content=teleop), fl.SplitItem(content=plot)])
    return fl.Layout(content=fl.SplitContainer(direction='row', items=[
        fl.SplitItem(proportion=2, content=scene), fl.SplitItem(proportion=1, content=side)]))


def layout_text(robot: str = ROBOT) -> str:
    """Return the layout as the bundled file holds it: indented JSON, one newline at the end."""
    return json.dumps(json.loads(lab_layout(robot).to_json()), indent=2) + '\n'


if __name__ == '__main__':
    print(layout_text(), end='')
