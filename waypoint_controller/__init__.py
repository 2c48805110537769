"""
waypoint_controller: the lab's answer, a controller that drives a robot through a waypoint file.

It stands on the lab's contract (waypoint_lab: the course, the goal set, the status texts and
topics) and not on the simulator: the node, its control law, the PIDs and the planner.
"""
