# tethersim: `make run` sets everything up and runs the default scene; `make test` sets up
# and runs the tests. Both are idempotent: a step runs again only when its inputs changed.

PYTHON ?= python3.11
VENV := .venv
STAMP_VENV := $(VENV)/.requirements-installed
STAMP_BUILD := install/.build-stamp
LIVE_CLIENT := test/live_client
STAMP_NODE := $(LIVE_CLIENT)/node_modules/.installed
SCENE ?= outdoor_flight
ARGS ?=

export AMENT_PREFIX_PATH := $(CURDIR)/$(VENV)

PKG_SOURCES := $(shell find src -type f \( -name '*.msg' -o -name 'CMakeLists.txt' -o -name 'package.xml' -o -name 'setup.py' -o -name 'setup.cfg' -o -path '*/scenes/*' \) 2>/dev/null)

.PHONY: setup build run test lint bench docs clean live-client

setup: $(STAMP_BUILD)

$(STAMP_VENV): requirements.txt tools/system-deps.sh
	@tools/system-deps.sh $(PYTHON)
	@test -x $(VENV)/bin/python || $(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -r requirements.txt
	@touch $@

$(STAMP_BUILD): $(STAMP_VENV) $(PKG_SOURCES) cmake/wheel_include_fix.cmake
	. $(VENV)/bin/activate && colcon --log-base build/log build --base-paths src --symlink-install \
		--event-handlers console_cohesion- status- \
		--cmake-args -DCMAKE_PROJECT_INCLUDE=$(CURDIR)/cmake/wheel_include_fix.cmake \
		-DPython3_EXECUTABLE=$(CURDIR)/$(VENV)/bin/python -DBUILD_TESTING=OFF
	@touch $@

build: $(STAMP_BUILD)

# the live view's test client (Foxglove's own protocol client and ROS 2 decoder, from npm, pinned by the lock file)
$(STAMP_NODE): $(LIVE_CLIENT)/package.json $(LIVE_CLIENT)/package-lock.json
	@command -v npm >/dev/null 2>&1 || { echo "tethersim: error: npm (Node.js 20) is needed for the live view's test client (e.g. sudo apt-get install nodejs npm)" >&2; exit 2; }
	npm ci --prefix $(LIVE_CLIENT) --ignore-scripts --no-audit --no-fund --loglevel=error
	@touch $@

live-client: $(STAMP_NODE)

run: $(STAMP_BUILD)
	./tethersim run $(SCENE) $(ARGS)

test: $(STAMP_BUILD) $(STAMP_NODE) lint
	./tethersim-env python -m pytest -q -n 2 --dist loadfile --no-loadscope-reorder src test $(ARGS)

# ruff over all Python, mypy over the plain-Python cores (pyproject.toml says which and how)
lint: $(STAMP_VENV)
	$(VENV)/bin/ruff check src test bench tools
	$(VENV)/bin/mypy

bench: $(STAMP_BUILD)
	@for bench in bench/*/run.py; do echo "== $$bench"; ./tethersim-env python $$bench || exit 1; done

# the docs' result blocks and picture from the commands that produce them (tools/docs.py; ARGS: block names)
docs: $(STAMP_BUILD)
	./tethersim-env python tools/docs.py $(ARGS)

clean:
	rm -rf build install log .cache $(VENV) $(LIVE_CLIENT)/node_modules
