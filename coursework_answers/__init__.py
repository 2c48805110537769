"""
The courseworks' reference answers: what a good submission does, and the baselines they set.

They stand on the courseworks' contract (courseworks/) as the lab's answer stands on the lab's;
the grader never imports them. mapper.py builds an occupancy grid from the laser; frontiers.py
picks where the explorer goes next; planner.py plans a route of straight legs to a goal.
"""
