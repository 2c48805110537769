#!/usr/bin/env bash
# The main job: stdr_lite and waypoint_controller as two processes on a bundled course, in
# lockstep. course_monitor prints every robot_status message as it arrives with a progress line
# and records the run; plot_run then draws it to run.png. The demo ends when the controller does
# and exits with its code.
set -euo pipefail
: "${ROS_AUTOMATIC_DISCOVERY_RANGE:?must be LOCALHOST; run through make demo}"
: "${ROS_DOMAIN_ID:?run through make demo}"
course=${COURSE:-$(python3 -c 'import sys; print(sys.prefix)')/share/simple_robot_control/waypoints/lab_tour.txt}
speed=${REAL_TIME_FACTOR:-4.0}
record=${RECORD:-run.jsonl}
picture=${PICTURE:-run.png}

stdr_lite --ros-args -p lockstep:=true -p real_time_factor:="$speed" --log-level warn &
simulator=$!
course_monitor "$course" --ros-args -p record_file:="$record" --log-level warn &
monitor=$!
trap 'kill -INT $simulator $monitor 2>/dev/null; wait $simulator $monitor 2>/dev/null || true' EXIT

echo "Course $course, at most ${speed}x real time (REAL_TIME_FACTOR=0: as fast as it goes):"
status=0
waypoint_controller "$course" --ros-args --log-level warn || status=$?
# The monitor ends by itself on FINISHED or ABORTED; after bad input there is nothing to wait for,
# and should the controller have died without a last word, the monitor is stopped after 10 s.
if [ "$status" -le 1 ]; then
    (sleep 10; kill -INT $monitor 2>/dev/null || true) &
    wait $monitor || true
    plot_run "$record" --output "$picture"
fi
exit "$status"
