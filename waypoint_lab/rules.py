"""
The lab's numbers and names, as the lab text gives them: plain data, no numpy.

course.py judges runs by them; the tools' parameter tables (parameters.py) take their defaults
from here, light enough to check a command line before any node's code loads.
"""

import math

# The goal set of a waypoint: within d metres, heading within t.
DISTANCE_TOLERANCE = 0.1
ANGLE_TOLERANCE = math.radians(5.0)
# Where the lab's robot starts (the lab's STDR launch puts robot0 there).
START = (1.0, 2.0, 0.0)
TIME_LIMIT = 120.0
# The course a controller follows when given none: a tour of the lab's room, installed in share.
BUNDLED_COURSE = ('waypoints', 'lab_tour.txt')
# The lab's task, by the name a course file gives it (the courseworks add theirs: courseworks).
WAYPOINTS_TASK = 'waypoints'
# The speeds the lab's robot is driven at unless a controller is told otherwise: the reference
# controller's limits and the learning task's action bounds.
MAX_LINEAR_SPEED = 0.5
MAX_ANGULAR_SPEED = 1.0
STATUS_TOPIC = 'robot_status'
# The course a controller follows, as a nav_msgs/Path (transient local): for RViz and bags.
COURSE_TOPIC = 'waypoints'
