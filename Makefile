# Set-up on a machine with nothing but Python 3: `make demo` or `make test`.
# Both create .venv on first use and install the package with ROS 2 Jazzy from PyPI wheels.

SHELL := /bin/bash
VENV := .venv
PYTHON := $(VENV)/bin/python
PIP := $(PYTHON) -m pip --disable-pip-version-check

# DDS stays on loopback, in a domain of this run's own (tests pick their own per session).
export ROS_AUTOMATIC_DISCOVERY_RANGE := LOCALHOST
export ROS_STATIC_PEERS :=
export ROS_DOMAIN_ID ?= $(shell shuf -i 1-100 -n 1)
# Peers found within about half a second rather than up to 3 s (see the file).
export FASTRTPS_DEFAULT_PROFILES_FILE ?= $(abspath config/fastdds_quick_discovery.xml)

.PHONY: demo lab-session swarm grade test test-quick test-unit test-node test-system check-stdr \
	bench install clean clean-cache

demo: install
	PATH="$(abspath $(VENV))/bin:$$PATH" scripts/demo.sh

lab-session: install
	PATH="$(abspath $(VENV))/bin:$$PATH" scripts/lab_session.sh

swarm: install
	PATH="$(abspath $(VENV))/bin:$$PATH" scripts/swarm.sh

# The tick-off sheet: grade_lab grades waypoint_controller on the bundled courses (grade_report/).
grade: install
	PATH="$(abspath $(VENV))/bin:$$PATH" grade_lab --courses waypoints --jobs 2 --lockstep \
		--real-time-factor 4 --report grade_report -- waypoint_controller {waypoints}

bench: install $(VENV)/.test-dependencies
	$(PYTHON) -m bench.controller
	$(PYTHON) -m bench.optimum
	$(PYTHON) -m bench.realtime
	$(PYTHON) -m bench.viewer
	$(PYTHON) -m bench.requests
	$(PYTHON) -m bench.recorder
	$(PYTHON) -m bench.learning

test: install $(VENV)/.test-dependencies
	$(PYTHON) -m pytest

# A developer's minute: the unit and node tiers on two workers (make test stays the whole suite).
test-quick: install $(VENV)/.test-dependencies
	$(PYTHON) -m pytest test/unit test/node

# One tier of the suite at a time: unit (pure logic), node (nodes in-process), system (executables).
test-unit test-node test-system: install $(VENV)/.test-dependencies
	$(PYTHON) -m pytest test/$(@:test-%=%)

# STDR's own robot files load unchanged: STDR_RESOURCES=<stdr_simulator>/stdr_resources/resources
check-stdr: install $(VENV)/.test-dependencies
	test -d "$(STDR_RESOURCES)/robots" || { echo 'check-stdr: set STDR_RESOURCES to the stdr_resources/resources folder of an stdr_simulator checkout' >&2; exit 2; }
	STDR_RESOURCES="$(abspath $(STDR_RESOURCES))" $(PYTHON) -m pytest -q test/unit/test_stdr_release_files.py

# Reading a robot's sensors once (from outside the tree, so the installed package is the one read)
# compiles the ray caster into numba's cache beside it: 2.5 s in a new venv, 1 s once cached; here
# rather than in the first run that reads a laser, whose simulator would stand still meanwhile.
install: $(VENV)/.dependencies $(VENV)/.interfaces
	rm -rf build
	$(PIP) install --quiet --no-deps --no-build-isolation --force-reinstall . 2> >(grep -v 'is ignored' >&2)
	cd / && $(abspath $(PYTHON)) -c 'import stdr_lite; stdr_lite.load_world().sensor_readings("robot0")'

# Interface packages the PyPI wheels lack (tf2_msgs), built into the venv when they do not import.
$(VENV)/.interfaces: $(VENV)/.dependencies scripts/build_interfaces.sh requirements/interfaces.txt $(shell find interfaces -type f)
	scripts/build_interfaces.sh $(VENV)
	touch $@

# What the nodes need; the test tools (pytest, the linters, colcon, OMPL) only for the tests
# and benchmarks, so that a first `make demo` installs what it runs and no more.
$(VENV)/.dependencies: requirements/ros-jazzy.txt setup.py
	test -x $(PYTHON) || python3 -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip setuptools wheel 2> >(grep -v 'is ignored' >&2)
	$(PIP) install --quiet -r requirements/ros-jazzy.txt . 2> >(grep -v 'is ignored' >&2)
	touch $@

$(VENV)/.test-dependencies: $(VENV)/.dependencies requirements/test.txt
	$(PIP) install --quiet -r requirements/test.txt 2> >(grep -v 'is ignored' >&2)
	touch $@

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache

# The interface builds kept for other clones on this machine (scripts/build_interfaces.sh).
INTERFACES_CACHE_DIR := $(or $(SIMPLE_ROBOT_CONTROL_CACHE),$(or $(XDG_CACHE_HOME),$(HOME)/.cache)/simple_robot_control)/interfaces
clean-cache:
	rm -rf "$(INTERFACES_CACHE_DIR)"
