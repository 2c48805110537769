"""waypoint_controller: drive a robot through a waypoint file and report on robot_status."""
