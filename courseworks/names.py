"""
The courseworks' names: tasks and topics, as course files and submissions use them.

Plain data, light to load: the nodes' parameter tables take their defaults from here before
any judge's code (scipy, the compiled rays) loads. No ROS here.
"""

MAPPING, EXPLORATION, PLANNING = 'mapping', 'exploration', 'planning'
# Where a mapping submission publishes its nav_msgs/OccupancyGrid (the world's /map is the
# simulator's, hidden by the task): the topic the grader judges.
SUBMITTED_MAP_TOPIC = '/coursework_map'
# The tasks whose robot builds its own map: the simulator keeps the world's map to itself.
HIDES_MAP = (MAPPING, EXPLORATION)
