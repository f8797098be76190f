# Two commands do everything on a fresh Debian machine:
#   make demo   install what is missing, then run the default scene
#   make test   install what is missing, then run the test suite (all of it,
#               the slow FE cases too: a few minutes, measured in
#               docs/performance.md; "make test-fast" runs the default selection)
# Both are idempotent: a second call installs nothing.
#
# The current DOLFINx (PyPI dolfinx-solver-real) runs beside Debian's 0.5.2:
#   make setup-latest  a second venv, .venv-latest, on Python >= 3.12
#   make test-latest   the default test selection there (FE included)

VENV    ?= .venv
PY      := $(VENV)/bin/python
DEBS    := python3-dolfinx-real python3-gmsh python3-meshio python3-matplotlib python3-pandas python3-venv python3-dev libosmesa6 \
           libopenblas0-pthread
SUDO    := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DEMO_OUT ?= results/demo
# pytest-xdist: the tests run in TEST_JOBS processes, each module's tests in one
# of them (its module fixtures computed once). Most of a fresh clone's test time
# is numba compiling each law's loops; two processes compile side by side.
TEST_JOBS ?= 2
PYTEST := -m pytest -q -n $(TEST_JOBS) --dist loadscope

VENV_LATEST ?= .venv-latest
PY_LATEST   := $(VENV_LATEST)/bin/python
# Interpreters tried for the second stack, first match >= 3.12 wins (Debian
# bookworm has only 3.11); without one, uv (from PyPI) downloads a CPython 3.12
# build (python-build-standalone, from GitHub), else setup-latest stops and says so.
PYTHONS_LATEST ?= python3.12 $(HOME)/.pyenv/versions/3.12*/bin/python python3.13 \
                  $(HOME)/.pyenv/versions/3.13*/bin/python
UV_VENV     := .venv-uv

.PHONY: demo test test-fast test-latest bench bench-full docs figures setup setup-latest clean clean-cache

# The paper's Fig 7 scene (longitudinal, k_v = 6) to 0.3 s, FE and analytic
# (--force: a second make demo replaces the first one's results).
demo: $(VENV)/.warm
	$(VENV)/bin/vibrofric run scenes/longitudinal.toml --set time.T=0.3 --out $(DEMO_OUT) --force

test: $(VENV)/.installed
	$(PY) $(PYTEST) -m ""

test-fast: $(VENV)/.installed
	$(PY) $(PYTEST)

test-latest: $(VENV_LATEST)/.installed
	$(PY_LATEST) $(PYTEST)

# Speed against error of every method (docs/performance.md, "Choosing settings"), then the
# analytic stepper's own timings (benchmarks/).
bench: $(VENV)/.warm
	$(VENV)/bin/vibrofric bench --quick --out results/bench --force
	$(PY) benchmarks/analytic_speed.py

bench-full: $(VENV)/.installed
	$(VENV)/bin/vibrofric bench --out results/bench-full --force

# The paper's Figs 6-12 (analytic, and FE points where the paper had Abaqus
# ones) into results/figures/, from the literate scripts examples/fig*.py
# (VIBROFRIC_FE=0: without the FE points; VIBROFRIC_FAST=1: the tests' quick form).
figures: $(VENV)/.installed
	@for script in examples/fig*.py; do echo "$$script"; $(PY) $$script || exit 1; done

# This documentation site (mkdocs.yml, docs/) into build/site; --strict: a broken
# link or any warning fails the build. Needs the docs extra (pip install -e '.[docs]').
docs: $(VENV)/.installed
	$(VENV)/bin/python -c "import mkdocs, material, mkdocstrings" 2>/dev/null || \
	  $(PY) -m pip install -q -c $(VENV)/constraints.txt -e '.[docs]'
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --quiet

setup: $(VENV)/.warm

setup-latest: $(VENV_LATEST)/.installed

# The Debian packages of $(1) that are missing, installed (apt-get, as root or through sudo).
define apt_install
	@missing=""; for p in $(1); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi
endef

# Debian's packages: DOLFINx 0.5 and everything built against it (numpy,
# numba, scipy, petsc4py, mpi4py) live under /usr/bin/python3. Without
# libopenblas0-pthread Debian's numpy and scipy run on the reference BLAS:
# the reduced model's set-up on the fine mesh spent 30 s in one dense product
# that OpenBLAS does in 0.5 s (it takes over libblas.so.3 by Debian's
# alternatives; numpy itself is not replaced).
$(VENV)/.debs: Makefile
	$(call apt_install,$(DEBS))
	/usr/bin/python3 -m venv --system-site-packages $(VENV)
	touch $@

# pip adds only what Debian lacks; the constraints pin Debian's numpy, numba,
# scipy and matplotlib so that no pip package can replace them (under DOLFINx;
# a pip matplotlib beside Debian's mpl_toolkits warns at every run that Axes3D
# cannot be imported).
$(VENV)/.installed: $(VENV)/.debs pyproject.toml
	$(PY) -c "import numpy, numba, scipy, matplotlib; print('\n'.join(f'{m.__name__}=={m.__version__}' for m in (numpy, numba, scipy, matplotlib)))" > $(VENV)/constraints.txt
	$(PY) -m pip install -q -c $(VENV)/constraints.txt -e '.[test]'
	touch $@

# numba compiles every loop per friction law on first use (minutes for all of
# them): compiled here for the built-in laws, once (docs/first-answer.md).
$(VENV)/.warm: $(VENV)/.installed
	$(PY) -m vibrofric.warm
	touch $@

# The current DOLFINx from PyPI: dolfinx-solver-real brings DOLFINx with real
# PETSc, petsc4py, mpi4py and MPICH (its own mpirun in $(VENV_LATEST)/bin; never
# install PyPI petsc4py beside it); pip picks numpy, numba and scipy to fit.
# ffcx compiles the forms with the C compiler (gcc).
$(VENV_LATEST)/.installed: pyproject.toml
	$(call apt_install,python3-venv gcc)
	@if [ ! -x $(PY_LATEST) ]; then \
	  python=""; for p in $(PYTHONS_LATEST); do \
	    if command -v $$p >/dev/null 2>&1 && \
	       $$p -c 'import sys, venv; sys.exit(sys.version_info < (3, 12))' 2>/dev/null; then \
	      python=$$p; break; \
	    fi; \
	  done; \
	  if [ -z "$$python" ]; then \
	    echo "no Python >= 3.12 here: installing one with uv"; \
	    /usr/bin/python3 -m venv $(UV_VENV) && $(UV_VENV)/bin/pip install -q uv && \
	    $(UV_VENV)/bin/uv python install 3.12 && \
	    python=$$($(UV_VENV)/bin/uv python find 3.12) || { \
	      echo "make setup-latest: no Python >= 3.12 (tried: $(PYTHONS_LATEST)) and uv could" \
	           "not download one: install one, or name it with PYTHONS_LATEST=/path/to/python3.12" >&2; \
	      exit 1; }; \
	  fi; \
	  echo "$(VENV_LATEST) from $$python"; \
	  $$python -m venv $(VENV_LATEST) || exit 1; \
	fi
	$(PY_LATEST) -m pip install -q dolfinx-solver-real gmsh meshio -e '.[test]'
	$(PY_LATEST) -c "import mpi4py.MPI, dolfinx, numba, numpy, gmsh; \
	  print(f'$(VENV_LATEST): DOLFINx {dolfinx.__version__}, numpy {numpy.__version__}, numba {numba.__version__}, gmsh {gmsh.__version__}')"
	touch $@

# numba's compiled functions (the per-law loops recompile by themselves after an
# edit) and vibrofric's cache: meshes and FE models (vibrofric/disk_cache.py)
CACHE_DIR := $(or $(VIBROFRIC_CACHE),$(or $(XDG_CACHE_HOME),$(HOME)/.cache)/vibrofric)
clean-cache:
	find vibrofric \( -name '*.nbi' -o -name '*.nbc' -o -name '*.nbi.lock' \) -delete
	rm -rf "$(CACHE_DIR)" $(VENV)/.warm $(VENV_LATEST)/.warm

clean: clean-cache
	rm -rf $(VENV) $(VENV_LATEST) $(UV_VENV) results .pytest_cache
