#!/usr/bin/env bash
# Ten lab robots with lasers and sonars in the lab room, seen in stdr_viewer. Each robot drives
# a slow circle of its own. With a display the viewer opens a window (close it to end); without
# one (or with SECONDS_TO_RUN set) it runs offscreen for that long and saves its last frame.
set -euo pipefail
: "${ROS_AUTOMATIC_DISCOVERY_RANGE:?must be LOCALHOST; run through make swarm}"
: "${ROS_DOMAIN_ID:?run through make swarm}"
share=$(python3 -c 'import sys; print(sys.prefix)')/share/simple_robot_control
screenshot=${SCREENSHOT:-swarm.png}

stdr_lite --ros-args -p robots_file:="$share/robots/swarm_of_ten.yaml" --log-level warn &
simulator=$!
trap 'kill -INT $simulator 2>/dev/null; wait $simulator 2>/dev/null || true' EXIT
python3 "$(dirname "$0")/swarm_driver.py" &
if [ -z "${DISPLAY:-}" ] || [ -n "${SECONDS_TO_RUN:-}" ]; then
    export SDL_VIDEODRIVER=dummy
    stdr_viewer --ros-args -p screenshot:="$screenshot" &
    viewer=$!
    sleep "${SECONDS_TO_RUN:-6}"
    kill -INT $viewer
    wait $viewer
else
    stdr_viewer --ros-args -p screenshot:="$screenshot"
fi
