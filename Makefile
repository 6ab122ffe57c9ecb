# roughlight: `make study` runs the default study, `make test` the tests.
# Both set everything up first: Debian's libosmesa6 (and chromium for the
# report's browser test) through apt-get when missing, and the pinned Python
# packages (requirements.lock) into the project virtual environment .venv.

SHELL := /bin/bash
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
CORES ?= 2
UV_VERSION := 0.13.9
# Debian packages: a command to run as root (empty when we are root)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
export PYOPENGL_PLATFORM := osmesa

.PHONY: setup system-deps chromium study test bench style lint clean

setup: system-deps $(STAMP)

system-deps:
	@if ! ldconfig -p | grep -q 'libOSMesa\.so'; then \
		echo "installing Debian's libosmesa6 (OSMesa, software OpenGL)"; \
		$(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq libosmesa6 >/dev/null; \
	fi
	@ldconfig -p | grep -q 'libOSMesa\.so' || { echo "libOSMesa is still missing: install Debian's libosmesa6" >&2; exit 1; }

$(STAMP): requirements.lock pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q "uv==$(UV_VERSION)"
	# compile bytecode at install: importing pyrender and trimesh from source costs seconds per job
	$(BIN)/uv pip install -q --python $(BIN)/python --compile-bytecode -r requirements.lock
	$(BIN)/uv pip install -q --python $(BIN)/python --no-deps -e .
	@touch $(STAMP)

# browser for the report's test (Debian's chromium)
chromium:
	@command -v chromium >/dev/null || { $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq chromium >/dev/null; }

study: setup
	$(BIN)/snakemake --cores $(CORES)

test: setup chromium style
	$(BIN)/python -m pytest -q

# the full-size speed/accuracy benchmark and stability scans (results/benchmarks/full/, results/stability/full/),
# and the report built with them
bench: setup
	$(BIN)/snakemake --cores $(CORES) --config 'measurements={plan: full}'

# style: ruff over the Python, snakefmt over the rules (as the workflow catalog's template); part of `make test`
style: setup
	$(BIN)/ruff check src tests workflow/scripts
	$(BIN)/snakefmt --check Snakefile workflow/rules

lint: style
	$(BIN)/snakemake --lint

clean:
	rm -rf results .snakemake
