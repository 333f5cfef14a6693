# Two commands for a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP_DEV := $(VENV)/.dev-installed
STAMP_DEMO := $(VENV)/.demo-installed

.PHONY: demo test lint typecheck unit bench clean browser-deps

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(STAMP_DEMO): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[demo]'
	touch $@

$(STAMP_DEV): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@ $(STAMP_DEMO)

demo: $(STAMP_DEMO)
	$(PY) -m posekit.demos.main

lint: $(STAMP_DEV)
	$(VENV)/bin/ruff check src tests benchmarks

typecheck: $(STAMP_DEV)
	$(VENV)/bin/mypy

# Debian's chromium, a font, graphviz and three.js (npm ci from the committed lockfile) for the
# viewer's browser tests and view_frames' PDF. Without root the browser tests skip and say why.
browser-deps:
	bash scripts/install_browser_deps.sh || echo "browser-deps: not installed; browser tests will skip"

unit: $(STAMP_DEV) browser-deps
	$(PY) -m pytest

test: lint typecheck unit

bench: $(STAMP_DEV)
	for b in benchmarks/*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info .pytest_cache .mypy_cache .ruff_cache
