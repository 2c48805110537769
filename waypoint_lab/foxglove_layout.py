"""
The lab's scene as a Foxglove layout, in the file format the Foxglove app imports and exports.

The panels are built with Foxglove's own layout types (foxglove-sdk), whose JSON is the SDK's
tree of containers (for its notebook widget). The app's "Import from file" reads another
format, the one it exports: `configById` (each panel's config under an id `<panel type>!<name>`,
its title as `foxglovePanelTitle`), `layout` (a binary tree of those ids, as the app's
react-mosaic keeps it: first, second, direction, splitPercentage), `globalVariables`,
`userNodes` and `playbackConfig`. app_layout() turns the one into the other.

The bundled file config/foxglove_lab_layout.json is what this prints (a test keeps them equal):
the 3D panel on the map frame with the map, the course, the robot's lasers and the simulator's
markers; robot_status as it comes; the Teleop panel driving the robot through its cmd_vel; and
its sonars' ranges plotted (the 3D panel draws no sensor_msgs/Range).

    python -m waypoint_lab.foxglove_layout > config/foxglove_lab_layout.json
"""

import json

import foxglove.layouts as fl
from waypoint_lab.parameters import COURSE_PARAMETERS
from waypoint_lab.rules import COURSE_TOPIC, STATUS_TOPIC

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


# The SDK's panel types the app names otherwise (the others are named alike).
APP_PANEL_TYPES = {'ThreeDee': '3D'}


def app_layout(layout: fl.Layout) -> dict:
    """Return layout in the Foxglove app's import and export format (see the module)."""
    configs = {}

    def place(content):
        if content['type'] == 'panel':
            kind = APP_PANEL_TYPES.get(content['panelType'], content['panelType'])
            panel_id = f'{kind}!lab{len(configs)}'
            config = dict(content.get('config') or {})
            if content.get('title'):
                config['foxglovePanelTitle'] = content['title']
            configs[panel_id] = config
            return panel_id
        if content['type'] != 'split':
            raise ValueError(f'a {content["type"]} container has no place in the lab layout')
        return split(content['direction'], content['items'])

    def split(direction, items):
        first, rest = items[0], items[1:]
        if not rest:
            return place(first['content'])
        weights = [item.get('proportion', 1) for item in items]
        return {'first': place(first['content']), 'second': split(direction, rest),
                'direction': direction, 'splitPercentage': 100 * weights[0] / sum(weights)}

    tree = place(json.loads(layout.to_json())['content'])
    return {'configById': configs, 'globalVariables': {}, 'userNodes': {},
            'playbackConfig': {'speed': 1.0}, 'layout': tree}


def layout_text(robot: str = ROBOT) -> str:
    """Return the layout as the bundled file holds it: indented JSON, one newline at the end."""
    return json.dumps(app_layout(lab_layout(robot)), indent=2) + '\n'


if __name__ == '__main__':
    print(layout_text(), end='')
