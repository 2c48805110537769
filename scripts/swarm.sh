#!/usr/bin/env bash
# Ten lab robots with lasers and sonars in the lab room, seen in stdr_viewer. Each robot drives
# a slow circle of its own. With a display the viewer opens a window (close it to end); without
# one (or with SECONDS_TO_RUN set) it runs offscreen: once it shows the map and the robots, for
# SECONDS_TO_RUN (6) seconds more, then saves its last frame. Everything it starts is stopped
# when it ends, however it ends.
set -euo pipefail
: "${ROS_AUTOMATIC_DISCOVERY_RANGE:?must be LOCALHOST; run through make swarm}"
: "${ROS_DOMAIN_ID:?run through make swarm}"
share=$(python3 -c 'from simple_robot_control.share import share_directory; print(share_directory())')
screenshot=${SCREENSHOT:-swarm.png}
# How long the viewer may take to show the run, on a slow or loaded machine (s).
SHOW_WITHIN=${SHOW_WITHIN:-120}
log=$(mktemp)
started=()
stop_all() {
    for pid in "${started[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${started[@]}"; do wait "$pid" 2>/dev/null || true; done
    rm -f "$log"
}
trap stop_all EXIT

stdr_lite --ros-args -p robots_file:="$share/robots/swarm_of_ten.yaml" --log-level warn &
started+=($!)
python3 "$(dirname "$0")/swarm_driver.py" &
started+=($!)
if [ -n "${DISPLAY:-}" ] && [ -z "${SECONDS_TO_RUN:-}" ]; then
    stdr_viewer --ros-args -p screenshot:="$screenshot"
    exit
fi
export SDL_VIDEODRIVER=dummy
rm -f "$screenshot"
stdr_viewer --ros-args -p screenshot:="$screenshot" > "$log" 2>&1 &
viewer=$!
started+=("$viewer")
waited=0
until grep -q 'showing the map' "$log"; do
    if ! kill -0 "$viewer" 2>/dev/null || [ "$waited" -ge $((SHOW_WITHIN * 10)) ]; then
        cat "$log" >&2
        echo "swarm: stdr_viewer showed no run within ${SHOW_WITHIN} s: no picture" >&2
        exit 1
    fi
    sleep 0.1
    waited=$((waited + 1))
done
echo "swarm: the run is shown; a picture in ${SECONDS_TO_RUN:-6} s"
sleep "${SECONDS_TO_RUN:-6}"
kill -INT "$viewer"
wait "$viewer" || true
if [ ! -s "$screenshot" ]; then
    cat "$log" >&2
    echo "swarm: stdr_viewer wrote no $screenshot" >&2
    exit 1
fi
echo "swarm: wrote $screenshot"
