"""stdr_lite: a small STDR-equivalent simulator for unicycle robots in ROS 2."""
