# roughlight: `make study` runs the default study, `make test` the tests.
# Both set everything up first: Debian's libosmesa6, libllvm19 (Mitsuba's
# LLVM variant), a C compiler (the random tiles' counting kernel) and chromium
# (the report's browser test) through apt-get when missing, and the pinned
# Python packages (requirements.lock) into the project virtual environment .venv.

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

.PHONY: setup system-deps chromium slurm study test cluster-test claim-pilots claim-third-round claim-fourth-round claim-fifth-round claim-sixth-round claim-seventh-round claim-eighth-round bench every-view budget style lint clean

# the project's own bytecode too, at every setup (only what changed): where PYTHONDONTWRITEBYTECODE is set (as on
# this machine) every job would otherwise compile the package's modules from source, 0.1-0.2 s a sweep job
setup: system-deps $(STAMP)
	@$(BIN)/python -m compileall -q src
	@# the C kernels (render/fast/raster.c, render/exact/pyramid.c) built once, not by each of the first jobs
	@$(BIN)/python -c "from roughlight.render.fast import raster; raster.compile_kernel()"
	@$(BIN)/python -c "from roughlight.render.exact import pyramid; pyramid.build_kernel()"

# OpenGL headless, both platforms (render.platform): OSMesa (libosmesa6) and EGL's device route (libegl1 with
# Mesa's EGL and drivers, whose software device is llvmpipe; on GPU nodes the driver's EGL takes its place); and
# Debian's libllvm19 for Mitsuba's llvm_ad_rgb variant (render.method mitsuba: the project points Dr.Jit at LLVM 19
# itself, never at LLVM 15, whose first render aborts; without it the method falls back to scalar_rgb with a line in
# the log, so a failed install is said, not fatal)
EGL_PACKAGES := libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0
system-deps:
	@if ! ldconfig -p | grep -q 'libOSMesa\.so' || ! ldconfig -p | grep -q 'libEGL\.so\.1' \
		|| ! ldconfig -p | grep -q 'libOpenGL\.so\.0' || ! ls /usr/share/glvnd/egl_vendor.d/*mesa* >/dev/null 2>&1; then \
		echo "installing Debian's libosmesa6 and EGL (software OpenGL: OSMesa and EGL)"; \
		$(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq libosmesa6 $(EGL_PACKAGES) >/dev/null; \
	fi
	@ldconfig -p | grep -q 'libOSMesa\.so' || { echo "libOSMesa is still missing: install Debian's libosmesa6" >&2; exit 1; }
	@ldconfig -p | grep -q 'libEGL\.so\.1' || { echo "libEGL is still missing: install Debian's $(EGL_PACKAGES)" >&2; exit 1; }
	@if ! command -v "$${CC:-cc}" >/dev/null; then \
		echo "installing Debian's gcc (the random tiles' counting kernel, render/fast/raster.c)"; \
		$(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq gcc libc6-dev >/dev/null; \
	fi
	@command -v "$${CC:-cc}" >/dev/null || { echo "no C compiler ($${CC:-cc}): install Debian's gcc" >&2; exit 1; }
	@if ! ldconfig -p | grep -q 'libLLVM\.so\.19\|libLLVM-19\.so'; then \
		echo "installing Debian's libllvm19 (Mitsuba's LLVM variant)"; \
		$(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq libllvm19 >/dev/null \
			|| echo "libllvm19 could not be installed: render.method mitsuba will render in scalar_rgb" >&2; \
	fi

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

# a single-node SLURM for the cluster test (Debian's packages; their services are kept from starting: the test
# starts munged, slurmctld and slurmd itself and stops them by their PIDs)
SLURM_PACKAGES := slurmctld slurmd slurm-client munge
slurm:
	@if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then \
		echo "installing Debian's $(SLURM_PACKAGES)"; \
		printf '#!/bin/sh\nexit 101\n' | $(SUDO) tee /usr/sbin/policy-rc.d >/dev/null; \
		$(SUDO) chmod +x /usr/sbin/policy-rc.d; \
		$(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq \
			--no-install-recommends $(SLURM_PACKAGES) >/dev/null; status=$$?; \
		$(SUDO) rm -f /usr/sbin/policy-rc.d; exit $$status; \
	fi

study: setup
	$(BIN)/snakemake --cores $(CORES)

# the suite on both cores (pytest-xdist): each worker its own OSMesa contexts and temporary workflow copies
TEST_WORKERS ?= 2
test: setup chromium slurm style
	$(BIN)/python -m pytest -q -n $(TEST_WORKERS)

# the study on a single-node SLURM brought up here, through profiles/slurm, against a local run (a few minutes)
cluster-test: setup slurm
	$(BIN)/python -m pytest -q tests/test_cluster.py

# the claim's pilots rendered again (every ensemble's, claims.registered_pilots off) and their readings registered
# in config/claim_pilots.csv, printing which moved (docs/random-roughness.md); commit the file with the design
claim-pilots: setup
	$(BIN)/snakemake --cores $(CORES) results/analysis/random_claim_pilots.csv --config 'claims={registered_pilots: ""}'
	$(BIN)/python -m roughlight.study.pilots results/analysis/random_claim_pilots.csv config/claim_pilots.csv

# the claim's third round (docs/random-roughness.md, "A third round"): planned from a finished run's second round,
# its fresh tiles measured (results/claims/third, about a minute) and their readings registered in
# config/claim_third_round.csv, which the verdict then reads (claims.registered_third_round); commit the file
claim-third-round: setup
	$(BIN)/snakemake --cores $(CORES) results/analysis/random_claims_round2.csv --config 'claims={registered_third_round: ""}'
	$(BIN)/python -m roughlight.analysis.third_round results/analysis config/claim_third_round.csv

# the claim's rounds of its own direction (docs/random-roughness.md, "A fourth round" to "A sixth round"): the
# shape tests still undecided after the rounds before, read one-sided (the claim's direction against the
# instrument's margin), planned from a finished run's earlier rounds, their fresh tiles measured
# (results/claims/{fourth,fifth,sixth}, minutes; the sixth plans from the fifth's tiles, bootstrapped) and their
# readings registered in config/claim_{fourth,fifth,sixth}_round.csv (claims.registered_*_round); commit the file
ROUND_fourth := 4
ROUND_fifth := 5
ROUND_sixth := 6
ROUND_seventh := 7
ROUND_eighth := 8
claim-fourth-round claim-fifth-round claim-sixth-round claim-seventh-round claim-eighth-round: claim-%-round: setup
	$(BIN)/snakemake --cores $(CORES) results/analysis/random_claims_round2.csv --config 'claims={registered_$*_round: ""}'
	$(BIN)/python -m roughlight.analysis.direction_rounds results/analysis config/claim_$*_round.csv \
		--round $(ROUND_$*)

# the full-size speed/accuracy benchmark and stability scans (results/benchmarks/full/, results/stability/full/),
# and the report built with them
bench: setup
	$(BIN)/snakemake --cores $(CORES) --config 'measurements={plan: full}' --configfile config/export_fine.yaml

# every view of the study's random sweeps (both kinds, two seeds, the random grid's lowest and highest corner)
# against the exact reference: results/benchmarks/every_view/summary.csv (most of its time is the reference)
every-view: setup
	$(BIN)/snakemake --cores $(CORES) results/benchmarks/every_view/summary.csv

# style: ruff over the Python, snakefmt over the rules (as the workflow catalog's template); part of `make test`
style: setup
	$(BIN)/ruff check src tests workflow/scripts
	$(BIN)/snakefmt --check Snakefile workflow/rules

# the default workflow from a clean results/ (in a temporary copy of this tree: yours stay) against its budgets:
# wall time, the largest job's memory, the time by part (docs/budgets.md)
budget: setup
	$(BIN)/python tests/budget.py --cores $(CORES) $(if $(BASE),--baseline $(BASE))

lint: style
	$(BIN)/snakemake --lint

clean:
	rm -rf results .snakemake
