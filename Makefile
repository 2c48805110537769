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

# What is kept across clones: the interface builds, the training venv (see scripts/).
CACHE_DIR := $(or $(SIMPLE_ROBOT_CONTROL_CACHE),$(or $(XDG_CACHE_HOME),$(HOME)/.cache)/simple_robot_control)
TRAIN_VENV := $(CACHE_DIR)/train-venv-jax

.PHONY: demo lab-session swarm scenario grade test test-quick test-unit test-node test-system check-stdr fresh-linux \
	test-without-ros \
	bench train demo-policy install clean clean-cache

demo: install
	PATH="$(abspath $(VENV))/bin:$$PATH" scripts/demo.sh

lab-session: install
	PATH="$(abspath $(VENV))/bin:$$PATH" scripts/lab_session.sh

swarm: install
	PATH="$(abspath $(VENV))/bin:$$PATH" scripts/swarm.sh

# A coursework scenario in one command: make scenario SCENARIO=factory_planning (scenarios/).
scenario: install
	PATH="$(abspath $(VENV))/bin:$$PATH" SCENARIO="$(SCENARIO)" scripts/scenario.sh

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
	$(PYTHON) -m bench.live_view
	$(PYTHON) -m bench.learning
	$(PYTHON) -m bench.courseworks
	$(PYTHON) -m bench.grading

# A policy learned end to end: PPO (skrl on JAX, on the CPU) trains on the lab's task for
# TRAIN_MINUTES in a venv of its own beside the interface builds (JAX and skrl never enter
# .venv; JAX's wheels on PyPI are CPU-only, so no CUDA package is fetched: 332 MB in all
# from PyPI alone), writes waypoints_ppo.npz (numpy alone runs it), prints its success on 200
# held-out courses, then grade_lab grades it driving the bundled courses through ROS, in lockstep.
TRAIN_MINUTES ?= 20
TRAINING_STACK := 'skrl[jax]==2.1.1' jax==0.10.2 jaxlib==0.10.2
train: install
	test -x "$(TRAIN_VENV)/bin/python" || python3 -m venv "$(TRAIN_VENV)"
	rm -rf build
	"$(TRAIN_VENV)/bin/python" -m pip install --quiet --disable-pip-version-check \
		$(TRAINING_STACK) . 2> >(grep -v 'is ignored' >&2)
	cd / && "$(TRAIN_VENV)/bin/python" "$(CURDIR)/scripts/train_policy.py" \
		--minutes $(TRAIN_MINUTES) --output "$(CURDIR)/waypoints_ppo.npz"
	PATH="$(abspath $(VENV))/bin:$$PATH" grade_lab --courses waypoints --jobs 2 --lockstep \
		--real-time-factor 4 --report policy_report -- policy_controller {waypoints} \
		--ros-args -p policy:="$(CURDIR)/waypoints_ppo.npz"

# The lab tour driven by the shipped policy (POLICY=waypoints_ppo.npz for one of make train's).
demo-policy: install
	PATH="$(abspath $(VENV))/bin:$$PATH" CONTROLLER=policy_controller scripts/demo.sh

# In-process tests import the package from this tree: its compiled code (the simulator's core, the
# learning task's passes) goes into the tree's numba cache first (as install does for the
# installed copy), not in the middle of a test.
WARM_COMPILED := -c 'from stdr_lite.core.warm_up import compile_core; compile_core(); \
	from waypoint_lab.learning.task import compile_task; compile_task(); \
	from courseworks.rays import warm_up; warm_up()'

# The slowest tests are listed at the end: the suite is a budget (240 s of pytest here).
test: install $(VENV)/.test-dependencies
	$(PYTHON) $(WARM_COMPILED)
	$(PYTHON) -m pytest --durations=15

# A developer's minute: the unit and node tiers (make test stays the whole suite).
test-quick: install $(VENV)/.test-dependencies
	$(PYTHON) $(WARM_COMPILED)
	$(PYTHON) -m pytest test/unit test/node

# One tier of the suite at a time: unit (pure logic), node (nodes in-process), system (executables).
test-unit test-node test-system: install $(VENV)/.test-dependencies
	$(PYTHON) $(WARM_COMPILED)
	$(PYTHON) -m pytest test/$(@:test-%=%)

# The ROS-free side as a Mac or Windows user installs it (doc/python.md): `pip install .` into a
# venv of its own with no ROS wheel, where test/system/test_without_ros.py runs (the API, the
# environments, the policy, the judges, plot_run, and the ROS executables' one line).
NO_ROS_VENV := $(CACHE_DIR)/venv-without-ros
test-without-ros:
	rm -rf build "$(NO_ROS_VENV)" && python3 -m venv "$(NO_ROS_VENV)"
	"$(NO_ROS_VENV)/bin/python" -m pip install --quiet --disable-pip-version-check . pytest
	"$(NO_ROS_VENV)/bin/python" -m pytest --noconftest -o addopts= -p no:cacheprovider \
		test/system/test_without_ros.py

# Before a release: `make demo` as a newcomer runs it, on fresh Debian 12 and 13 root filesystems
# (as root, with debootstrap; DISTRIBUTIONS names others): scripts/fresh_linux.sh.
DISTRIBUTIONS ?=
fresh-linux:
	scripts/fresh_linux.sh $(DISTRIBUTIONS)

# STDR's own robot files load unchanged: STDR_RESOURCES=<stdr_simulator>/stdr_resources/resources
check-stdr: install $(VENV)/.test-dependencies
	test -d "$(STDR_RESOURCES)/robots" || { echo 'check-stdr: set STDR_RESOURCES to the stdr_resources/resources folder of an stdr_simulator checkout' >&2; exit 2; }
	STDR_RESOURCES="$(abspath $(STDR_RESOURCES))" $(PYTHON) -m pytest -q test/unit/test_stdr_release_files.py

# Stepping a small crowd and reading a laser once (from outside the tree, so the installed package
# is the one run) compiles the core into numba's cache beside it: 15 s in a new venv, 1 s once
# cached; here rather than in the first run that steps, whose simulator would stand still.
# Reinstalled only when a file the package is built from changed (every target runs install:
# a reinstall each time cost 10-40 s and broke tools running from the venv meanwhile).
PACKAGE_SOURCES := setup.py setup.cfg package.xml $(shell find simple_robot_control stdr_lite foxglove_live \
	waypoint_lab waypoint_controller lab_grader courseworks coursework_answers config maps robots obstacles launch \
	rviz resource sensor_files waypoints scenarios -type f -not -path '*/__pycache__/*' -not -name '*.pyc' 2>/dev/null)
install: $(VENV)/.installed
$(VENV)/.installed: $(VENV)/.dependencies $(VENV)/.interfaces $(PACKAGE_SOURCES)
	rm -rf build
	$(PIP) install --quiet --no-deps --no-build-isolation --force-reinstall . 2> >(grep -v 'is ignored' >&2)
	cd / && $(abspath $(PYTHON)) $(WARM_COMPILED)
	touch $@

# Interface packages the PyPI wheels lack (tf2_msgs), built into the venv when they do not import.
$(VENV)/.interfaces: $(VENV)/.dependencies scripts/build_interfaces.sh requirements/interfaces.txt $(shell find interfaces -type f)
	scripts/build_interfaces.sh $(VENV)
	touch $@

# What the nodes need; the test tools (pytest, the linters, colcon, OMPL) only for the tests
# and benchmarks, so that a first `make demo` installs what it runs and no more. The system's
# part is checked first (scripts/check_system.sh names what is missing); a venv left without
# pip by an earlier failure is made again.
$(VENV)/.dependencies: requirements/ros-jazzy.txt setup.py
	@scripts/check_system.sh
	$(PYTHON) -m pip --version >/dev/null 2>&1 || { rm -rf $(VENV) && python3 -m venv $(VENV); }
	$(PIP) install --quiet --upgrade pip setuptools wheel 2> >(grep -v 'is ignored' >&2)
	$(PIP) install --quiet -r requirements/ros-jazzy.txt . 2> >(grep -v 'is ignored' >&2)
	touch $@

$(VENV)/.test-dependencies: $(VENV)/.dependencies requirements/test.txt
	$(PIP) install --quiet -r requirements/test.txt 2> >(grep -v 'is ignored' >&2)
	touch $@

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache

# The interface builds kept for other clones on this machine (scripts/build_interfaces.sh).
INTERFACES_CACHE_DIR := $(CACHE_DIR)/interfaces
clean-cache:
	rm -rf "$(INTERFACES_CACHE_DIR)"
