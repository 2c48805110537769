#!/usr/bin/env bash
# A coursework scenario in one command (make scenario SCENARIO=factory_planning): stdr_lite with
# the scenario's world, robot and start, in lockstep, and its task's reference answer on the
# simulator's clock (use_sim_time), followed and recorded by course_monitor and drawn by
# plot_run, as make demo does the lab's. SCENARIO is a bundled scenario's name or a course
# file; CONTROLLER runs another controller (yours) in the place of the reference answer.
set -euo pipefail
: "${SCENARIO:?name one: make scenario SCENARIO=factory_planning}"
parameters=$(mktemp --suffix=.yaml)
trap 'rm -f "$parameters"' EXIT
setup=$(python3 "$(dirname "$0")/scenario_setup.py" "$SCENARIO" "$parameters")
status=0
line() { sed -n "$1p" <<< "$setup"; }
# Your CONTROLLER takes none of the reference's parameters, but its helpers (a mapper) stay.
answer_parameters=$(line 5)
[ -z "${CONTROLLER:-}" ] || answer_parameters=
COURSE=$(line 1) CONTROLLER=${CONTROLLER:-$(line 2)} PLOT_MAP=$(line 3) \
    PLOT_ROBOT_RADIUS=$(line 4) CONTROLLER_PARAMETERS=$answer_parameters HELPERS=$(line 6) \
    SIMULATOR_PARAMETERS=$parameters USE_SIM_TIME=true "$(dirname "$0")/demo.sh" || status=$?
exit "$status"
