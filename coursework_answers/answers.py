"""
Which bundled answer runs a scenario of each task: its controller, parameters and helper nodes.

Plain data, light to load (make scenario, scenario.launch.py and bench.grading read it before
any node starts). No ROS here.
"""

from dataclasses import dataclass, field

from courseworks.names import EXPLORATION, MAPPING, PLANNING, SUBMITTED_MAP_TOPIC
from waypoint_lab.rules import WAYPOINTS_TASK


@dataclass(frozen=True)
class Answer:
    """A task's bundled answer: the controller, its parameters, and the nodes run beside it."""

    controller: str
    parameters: dict = field(default_factory=dict)
    helpers: tuple[str, ...] = ()


REFERENCE_ANSWERS = {
    WAYPOINTS_TASK: Answer('waypoint_controller'),
    PLANNING: Answer('planner_controller'),
    MAPPING: Answer('planner_controller', {'map_topic': SUBMITTED_MAP_TOPIC, 'max_map_age': 1.5},
                    ('occupancy_mapper',)),
    EXPLORATION: Answer('planner_controller', {'map_topic': SUBMITTED_MAP_TOPIC,
                                               'max_map_age': 1.5, 'explore_for': 3600.0},
                        ('occupancy_mapper',)),
}
