#!/usr/bin/env bash
# The main job: stdr_lite and waypoint_controller as two processes on a bundled course, in
# lockstep. course_monitor prints every robot_status message as it arrives with a progress line
# and records the run; plot_run then draws it to run.png. The demo ends when the controller does
# and exits with its code. VIEWER=1 also opens stdr_viewer to watch the run live; VIEWER=foxglove
# serves it to Foxglove (foxglove_live) on localhost:${FOXGLOVE_PORT:-8765}, here or through ssh
# (FOXGLOVE_HOST=0.0.0.0 serves it on every interface: in a container, for a published port).
set -euo pipefail
: "${ROS_AUTOMATIC_DISCOVERY_RANGE:?must be LOCALHOST; run through make demo}"
: "${ROS_DOMAIN_ID:?run through make demo}"
share=$(python3 -c 'from simple_robot_control.share import share_directory; print(share_directory())')
course=${COURSE:-$share/waypoints/lab_tour.txt}
speed=${REAL_TIME_FACTOR:-4.0}
[[ $speed == *.* ]] || speed=$speed.0  # ROS wants a double parameter written as one
record=${RECORD:-run.mcap}
picture=${PICTURE:-run.png}

# LOCKSTEP=false for a controller that does not answer every odometry stamp (ours all do).
# SIMULATOR_PARAMETERS: a parameters file of stdr_lite's (a scenario's world: make scenario).
world=()
[ -z "${SIMULATOR_PARAMETERS:-}" ] || world=(--params-file "$SIMULATOR_PARAMETERS")
stdr_lite --ros-args "${world[@]}" -p lockstep:="${LOCKSTEP:-true}" \
    -p real_time_factor:="$speed" --log-level warn &
simulator=$!
rm -f "$record"
# MONITOR_PARAMETERS: name:=value words for course_monitor (a scenario's map topic to record).
monitor_parameters=()
for parameter in ${MONITOR_PARAMETERS:-}; do
    monitor_parameters+=(-p "$parameter")
done
course_monitor "$course" --ros-args -p bag:="$record" "${monitor_parameters[@]}" \
    --log-level warn &
monitor=$!
# Start the controller once the monitor has begun its bag: in lockstep nothing moves until
# the controller answers, by which time the monitor records the robot's odometry.
for _ in $(seq 100); do
    [ -s "$record" ] && break
    sleep 0.1
done
viewer=
if [ "${VIEWER:-}" = foxglove ]; then
    # Its line (where to connect) shows once it serves; the controller starts after it.
    live_log=$(mktemp)
    foxglove_live --ros-args -p port:="${FOXGLOVE_PORT:-8765}" \
        -p host:="${FOXGLOVE_HOST:-127.0.0.1}" --log-level warn \
        > >(tee "$live_log") 2>&1 &
    viewer=$!
    for _ in $(seq 100); do
        grep -q 'connect to ws://' "$live_log" && break
        kill -0 $viewer 2>/dev/null || break
        sleep 0.1
    done
    rm -f "$live_log"
    kill -0 $viewer 2>/dev/null || { echo 'demo: foxglove_live did not start' >&2; exit 1; }
    echo "Foxglove layout of the lab (Layouts, Import from file): $share/config/foxglove_lab_layout.json"
elif [ -n "${VIEWER:-}" ]; then
    # A window where there is a display; offscreen otherwise, leaving its last frame.
    if [ -z "${DISPLAY:-}" ]; then
        export SDL_VIDEODRIVER=dummy
        echo 'demo: no display ($DISPLAY is empty): stdr_viewer draws offscreen; its last frame goes to viewer.png'
    fi
    stdr_viewer --ros-args -p screenshot:=viewer.png --log-level warn &
    viewer=$!
fi
# HELPERS: nodes a scenario's answer runs beside its controller (a mapper), ended with the rest.
helpers=
for helper in ${HELPERS:-}; do
    "$helper" --ros-args --log-level warn &
    helpers="$helpers $!"
done
trap 'kill -INT $simulator $monitor $viewer $helpers 2>/dev/null; wait $simulator $monitor $viewer $helpers 2>/dev/null || true' EXIT

echo "Course $course, at most ${speed}x real time (REAL_TIME_FACTOR=0: as fast as it goes):"
# CONTROLLER=policy_controller drives with a learned policy (POLICY: its file; the shipped one).
# USE_SIM_TIME=true puts the controller's clock on the simulator's /clock.
policy=()
[ -z "${POLICY:-}" ] || policy=(-p "policy:=$POLICY")
[ -z "${USE_SIM_TIME:-}" ] || policy+=(-p "use_sim_time:=$USE_SIM_TIME")
# CONTROLLER_PARAMETERS: name:=value words for the controller (a scenario's answer's).
for parameter in ${CONTROLLER_PARAMETERS:-}; do
    policy+=(-p "$parameter")
done
"${CONTROLLER:-waypoint_controller}" "$course" --ros-args --log-level warn "${policy[@]}" &
controller=$!
status=0
wait -n -p ended $simulator $controller || status=$?
if [ "$ended" != "$controller" ]; then
    echo "demo: stdr_lite ended (exit code $status) before the controller finished" >&2
    kill -INT $controller 2>/dev/null || true
    exit 1
fi
# The monitor ends by itself on FINISHED or ABORTED; after bad input there is nothing to wait for,
# and should the controller have died without a last word, the monitor is stopped after 10 s.
if [ "$status" -le 1 ]; then
    for _ in $(seq 100); do
        kill -0 $monitor 2>/dev/null || break
        sleep 0.1
    done
    kill -INT $monitor 2>/dev/null || true
    wait $monitor || true
    # PLOT_MAP and PLOT_ROBOT_RADIUS: a scenario's world and robot (the lab's by default).
    plot=()
    [ -z "${PLOT_MAP:-}" ] || plot+=(--map "$PLOT_MAP")
    [ -z "${PLOT_ROBOT_RADIUS:-}" ] || plot+=(--robot-radius "$PLOT_ROBOT_RADIUS")
    plot_run "$record" --output "$picture" "${plot[@]}"
fi
exit "$status"
