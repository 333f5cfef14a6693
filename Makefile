# Two commands for a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP_DEV := $(VENV)/.dev-installed
STAMP_DEMO := $(VENV)/.demo-installed
# The reference peer: a real ROS 2 Jazzy rclpy on Fast DDS, in its own venv. Never posekit's
# dependency; differential and interoperability tests run scripts in it.
ROS2_VENV ?= .venv-ros2
ROS2_PACKAGES := ros-jazzy-rclpy ros-jazzy-rmw-fastrtps-cpp ros-jazzy-std-msgs \
	ros-jazzy-geometry-msgs ros-jazzy-nav-msgs ros-jazzy-sensor-msgs ros-jazzy-rosgraph-msgs \
	ros-jazzy-std-srvs
STAMP_ROS2 := $(ROS2_VENV)/.ros2-installed

.PHONY: demo test lint typecheck unit bench clean browser-deps ros2-ref

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

# The demo and the README's tour: posekit with every extra (plot, viewer, zenoh, bag, ...).
$(STAMP_DEMO): pyproject.toml setup.py $(wildcard src/posekit/*/_accel.c) | $(PY)
	$(PY) -m pip install --quiet -e '.[all]'
	touch $@

$(STAMP_DEV): pyproject.toml setup.py $(wildcard src/posekit/*/_accel.c) | $(PY)
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@ $(STAMP_DEMO)

demo: $(STAMP_DEMO)
	$(PY) -m posekit.demos.main
	@echo "posekit is installed in $(VENV): 'source $(VENV)/bin/activate' puts it on PATH"

lint: $(STAMP_DEV)
	$(VENV)/bin/ruff check src tests benchmarks

typecheck: $(STAMP_DEV)
	$(VENV)/bin/mypy

# Debian's chromium, a font and graphviz for the viewer's browser tests and view_frames' PDF
# (three.js is vendored in the package). Without root the browser tests skip and say why.
browser-deps:
	bash scripts/install_browser_deps.sh || echo "browser-deps: not installed; browser tests will skip"

$(STAMP_ROS2):
	$(PYTHON) -m venv $(ROS2_VENV)
	$(ROS2_VENV)/bin/python -m pip install --quiet $(ROS2_PACKAGES)
	touch $@

ros2-ref: $(STAMP_ROS2)

unit: $(STAMP_DEV) browser-deps $(STAMP_ROS2)
	$(PY) -m pytest

test: lint typecheck unit

bench: $(STAMP_DEV)
	for b in benchmarks/*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

clean:
	rm -rf $(VENV) $(ROS2_VENV) build *.egg-info src/*.egg-info .pytest_cache .mypy_cache .ruff_cache
