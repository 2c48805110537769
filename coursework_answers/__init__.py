"""
The courseworks' reference answers: what a good submission does, and the baselines they set.

They stand on the courseworks' contract (courseworks/) as the lab's answer stands on the lab's;
the grader never imports them. mapper.py builds an occupancy grid from the laser; frontiers.py
picks where the explorer goes next; planner.py plans a route of straight legs to a goal;
route_law.py drives a route per goal, and explorer_law.py explores before the goals, both as
control laws of the lab's run lifecycle. The nodes: planner_controller (the laws on the lab's
runner) and occupancy_mapper (the mapper); reference_run.py runs a course by the same laws and
mapper in the simulation core, without ROS.
"""
