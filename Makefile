# Two commands do everything on a fresh Debian machine:
#   make demo   install what is missing, then run the default scene
#   make test   install what is missing, then run the test suite (all of it,
#               the slow FE cases too: ~7 min on two cores; "make test-fast"
#               runs the default selection, ~2 min)
# Both are idempotent: a second call installs nothing.

VENV    ?= .venv
PY      := $(VENV)/bin/python
DEBS    := python3-dolfinx-real python3-gmsh python3-meshio python3-matplotlib python3-venv python3-dev libosmesa6
SUDO    := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DEMO_OUT ?= results/demo

.PHONY: demo test test-fast bench bench-full setup clean clean-cache

# The paper's Fig 7 scene (longitudinal, k_v = 6) to 0.3 s, FE and analytic
# (--force: a second make demo replaces the first one's results).
demo: $(VENV)/.installed
	$(VENV)/bin/vibrofric run scenes/longitudinal.toml --set time.T=0.3 --out $(DEMO_OUT) --force

test: $(VENV)/.installed
	$(PY) -m pytest -q -m ""

test-fast: $(VENV)/.installed
	$(PY) -m pytest -q

# Speed against error of every method (README "Choosing settings"), then the
# analytic stepper's own timings (benchmarks/).
bench: $(VENV)/.installed
	$(VENV)/bin/vibrofric bench --quick --out results/bench --force
	$(PY) benchmarks/analytic_speed.py

bench-full: $(VENV)/.installed
	$(VENV)/bin/vibrofric bench --out results/bench-full --force

setup: $(VENV)/.installed

# Debian's packages: DOLFINx 0.5 and everything built against it (numpy,
# numba, scipy, petsc4py, mpi4py) live under /usr/bin/python3.
$(VENV)/.debs:
	@missing=""; for p in $(DEBS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi
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

# numba's cache does not see edits to functions compiled into other files
clean-cache:
	find vibrofric -name '*.nbi' -delete -o -name '*.nbc' -delete

clean: clean-cache
	rm -rf $(VENV) results .pytest_cache
