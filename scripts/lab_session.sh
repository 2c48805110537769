#!/usr/bin/env bash
# Replays the lab's manual session: stdr_lite in the background, move_robot fed from a file.
set -euo pipefail
: "${ROS_AUTOMATIC_DISCOVERY_RANGE:?must be LOCALHOST; run through make lab-session}"
: "${ROS_DOMAIN_ID:?run through make lab-session}"
here=$(cd "$(dirname "$0")" && pwd)

stdr_lite &
simulator=$!
trap 'kill -INT $simulator 2>/dev/null; wait $simulator 2>/dev/null || true' EXIT

echo "Lab session (velocity m/s, rotation deg/s, duration s), as in the lab text:"
move_robot < "$here/lab_session.txt"
