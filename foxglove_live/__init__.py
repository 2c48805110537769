"""
foxglove_live: any run's ROS graph served live to Foxglove, over one port, here or through ssh.

live_view.py serves the graph's topics as Foxglove channels (foxglove-sdk's WebSocket server);
live_commands.py passes on what clients publish (Teleop's Twist), checked and bounded per
client; foxglove_live.py is the node and executable, parameters.py its table. It stands on the
shared floor only: the simulator, the lab and the grader know nothing of it.
"""
