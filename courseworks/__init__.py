"""
The module's courseworks after the lab: mapping, exploration and planning, and their judges.

No ROS here.
One home per rule: the grid a coursework is judged on (grids.py: walls grown by the robot,
reachable free space, shortest paths), rays cell by cell (rays.py, compiled), and a judge per
task (mapping.py, exploration.py, planning.py) over the ground truth; tasks.py says which tasks
a course file may ask and their thresholds, names.py the tasks' and topics' names and the
answers bundled for them. The lab's own task stays in waypoint_lab.
"""
