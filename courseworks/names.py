"""
The courseworks' names: tasks and topics, as course files and submissions use them.

Plain data, light to load: the nodes' parameter tables take their defaults from here before
any judge's code (scipy, the compiled rays) loads. No ROS here.
"""

from dataclasses import dataclass, field

from waypoint_lab.rules import WAYPOINTS_TASK

MAPPING, EXPLORATION, PLANNING = 'mapping', 'exploration', 'planning'
# Where a mapping submission publishes its nav_msgs/OccupancyGrid (the world's /map is the
# simulator's, hidden by the task): the topic the grader judges.
SUBMITTED_MAP_TOPIC = '/coursework_map'
# The tasks whose robot builds its own map: the simulator keeps the world's map to itself.
HIDES_MAP = (MAPPING, EXPLORATION)


@dataclass(frozen=True)
class Answer:
    """A task's bundled answer: the controller, its parameters, and the nodes run beside it."""

    controller: str
    parameters: dict = field(default_factory=dict)
    helpers: tuple[str, ...] = ()


# What a scenario of each task is run with (make scenario, scenario.launch.py).
REFERENCE_ANSWERS = {
    WAYPOINTS_TASK: Answer('waypoint_controller'),
    PLANNING: Answer('planner_controller'),
    MAPPING: Answer('planner_controller', {'map_topic': SUBMITTED_MAP_TOPIC, 'max_map_age': 1.5},
                    ('occupancy_mapper',)),
    EXPLORATION: Answer('planner_controller', {'map_topic': SUBMITTED_MAP_TOPIC,
                                               'max_map_age': 1.5, 'explore_for': 3600.0},
                        ('occupancy_mapper',)),
}
