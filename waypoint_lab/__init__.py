"""
The lab's contract: what every controller of the waypoint lab is asked to do and how it is read.

Written once here, for the reference controller (waypoint_controller), any student's, a learned
policy, and the grader alike: the course and its goal set (course.py), waypoint files
(waypoints.py), the robot_status texts (status.py), the topics and their QoS (interface.py), and a
recorded run read from a bag (run.py). The lab's tools stand on it: course_monitor, plot_run, and
the task as Gymnasium environments (learning/). The simulator (stdr_lite) knows none of it.
"""
