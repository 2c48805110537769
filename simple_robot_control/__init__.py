"""
simple_robot_control: what the package's nodes and tools share.

The node runtime (main loop, parameters, exit codes), pose conversions, number and name
checks, YAML and map_server map reading, and the lookup of the files the package installs.
"""
