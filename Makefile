# The two commands of the README:
#   make demo   - install what the demo needs (the render and sfm extras, the Debian
#                 packages it runs on) and run the example survey end to end (headless);
#                 its own render measures this machine's render speed
#   make test   - install everything and run the whole test suite (lint + pytest)
PYTHON ?= python3.11
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
PROBED := $(VENV)/.probed
DEMO_STAMP := $(VENV)/.installed-demo
, := ,

.PHONY: setup install system system-demo demo test lint bench clean

# everything: the packages, the compiled kernels and the probe render
setup: system $(PROBED)

# the packages and the compiled kernels, without the probe render
install: system $(STAMP)

# every Debian package: the demo's and those only the tests and the GUI use (Xvfb, the
# xcb libraries, CloudCompare, COLMAP's command line)
system:
	@bash scripts/install-system-packages.sh all

# the Debian packages the demo runs on (the C compiler, the libraries bpy loads)
system-demo:
	@bash scripts/install-system-packages.sh demo

# the compiled kernels are rebuilt by pip install when their sources change
KERNEL_SOURCES := pyproject.toml setup.py $(wildcard designer/csrc/*.h designer/evaluate/csrc/*.[ch] designer/core/csrc/*.c)

# a virtual environment with designer and the extras named (the kernels compiled), checked;
# the packages installed by uv (PyPI's, into the environment: a fresh clone's render and
# sfm extras in 13.5 s against pip's 37 s, no cache), by pip where uv cannot be had
define venv_install
	@command -v $(PYTHON) >/dev/null || { echo "error: $(PYTHON) not found; install Python 3.11 (the bpy wheels exist only for 3.11)"; exit 1; }
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet "uv>=0.5,<1" || true
	if test -x $(BIN)/uv; then $(BIN)/uv pip install --quiet --python $(BIN)/python -e ".[$(1)]"; \
	else $(BIN)/python -m pip install --quiet --upgrade pip && $(BIN)/python -m pip install --quiet -e ".[$(1)]"; fi
	$(BIN)/designer warmup --no-probe
endef

# every extra (render, sfm, cluster, gui, test); they hold the demo's too
$(STAMP): $(KERNEL_SOURCES)
	$(call venv_install,all)
	touch $(STAMP) $(DEMO_STAMP)

# the extras the demo runs on (render = bpy, sfm = pycolmap), without the GUI's Qt and
# VTK, Dask and the test tools
$(DEMO_STAMP): $(KERNEL_SOURCES)
	$(call venv_install,render$(,)sfm)
	touch $(DEMO_STAMP)

# the probe render: this machine's render speed, which every render-time estimate uses;
# the tests each keep their own empty render-speed cache (tests/conftest.py), so make
# test does without it, and so does make demo: its plan's estimate says it uses the
# reference figures until its own render (60 images) records this machine's speed
$(PROBED): $(STAMP)
	$(BIN)/designer warmup
	touch $(PROBED)

demo: system-demo $(DEMO_STAMP)
	$(BIN)/designer demo -o demo-output

lint: install
	$(BIN)/ruff check .

# two pytest workers (pytest-xdist), each taking whole test files: a file's module
# fixtures (a render shared by its tests) are made once; the 25 slowest are listed
test: install lint
	$(BIN)/python -m pytest -n 2 --dist loadfile --durations=25

bench: setup
	$(BIN)/designer bench core

clean:
	rm -rf $(VENV) demo-output .pytest_cache .ruff_cache
