#!/usr/bin/env bash
# A coursework scenario in one command (make scenario SCENARIO=factory_planning): stdr_lite with
# the scenario's world, robot and start, in lockstep, and its task's reference answer on the
# simulator's clock (use_sim_time), followed and recorded by course_monitor and drawn by
# plot_run, as make demo does the lab's; then judged by the task's judge as grade_lab judges
# it (scenario_judge.py: its check, and task.png, its reading of the world's cells). SCENARIO
# is a bundled scenario's name or a course file; CONTROLLER runs another controller (yours) in
# the place of the reference answer.
set -euo pipefail
: "${SCENARIO:?name one: make scenario SCENARIO=factory_planning}"
parameters=$(mktemp --suffix=.yaml)
trap 'rm -f "$parameters"' EXIT
setup=$(python3 "$(dirname "$0")/scenario_setup.py" "$SCENARIO" "$parameters")
status=0
line() { sed -n "$1p" <<< "$setup"; }
# Your CONTROLLER takes none of the reference's parameters, but its helpers (a mapper) stay
# unless HELPERS says otherwise (HELPERS= runs none).
answer_parameters=$(line 5)
# A mapping task's map topic: course_monitor records it too, for the judge.
map_topic=$(line 7)
[ -z "${CONTROLLER:-}" ] || answer_parameters=
COURSE=$(line 1) CONTROLLER=${CONTROLLER:-$(line 2)} PLOT_MAP=$(line 3) \
    PLOT_ROBOT_RADIUS=$(line 4) CONTROLLER_PARAMETERS=$answer_parameters HELPERS=${HELPERS-$(line 6)} \
    MONITOR_PARAMETERS=${map_topic:+map_topic:=$map_topic} \
    SIMULATOR_PARAMETERS=$parameters USE_SIM_TIME=true "$(dirname "$0")/demo.sh" || status=$?
[ "$status" -gt 1 ] || python3 "$(dirname "$0")/scenario_judge.py" "$SCENARIO" \
    "${RECORD:-run.mcap}" "${TASK_PICTURE:-task.png}" || status=$?
exit "$status"
