"""
lab_grader: the lab's tick-off sheet, automated: grade any controller against hidden courses.

Each course runs in isolation (stdr_lite, a recorder and the submission in a ROS domain of
their own) and is judged from what its recorder heard live against the simulator's ground
truth; the bag it also writes is for people to look at, never the evidence.
"""
