"""The simulation itself, with no ROS in it: kinematics, collisions, sensors, robots."""
