"""The stdr_lite node: the simulation core on ROS topics, parameters and timers."""
