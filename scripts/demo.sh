#!/usr/bin/env bash
# The main job: stdr_lite and waypoint_controller as two processes on a bundled course.
# Every robot_status message is printed as it arrives; the demo ends when the controller does.
set -euo pipefail
: "${ROS_AUTOMATIC_DISCOVERY_RANGE:?must be LOCALHOST; run through make demo}"
: "${ROS_DOMAIN_ID:?run through make demo}"
course=${COURSE:-$(python3 -c 'import sys; print(sys.prefix)')/share/simple_robot_control/waypoints/lab_tour.txt}
speed=${REAL_TIME_FACTOR:-4.0}

stdr_lite --ros-args -p real_time_factor:="$speed" --log-level warn &
simulator=$!
trap 'kill -INT $simulator 2>/dev/null; wait $simulator 2>/dev/null || true' EXIT

echo "Course $course at ${speed}x real time:"
waypoint_controller "$course" --ros-args -p use_sim_time:=true
