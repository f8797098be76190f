"""Compile at set-up, not at first use: ``python -m vibrofric.warm`` (``vibrofric warm``).

numba compiles every time loop for each friction law (friction_law/specialize.py)
and keeps what it compiled on disk. This runs a few steps of the Fig 7 scene
with each built-in law through each stepper and integrator, shot for its steady
cycle and stepped (METHODS), so that numba's
cache holds every built-in law's loops and the model cache (fem/model/model_cache.py)
the default block: the first ``vibrofric run`` or ``analytic`` after
``make setup`` (which runs this) compiles nothing. A user's law still
compiles on its first run, and says so.

It says what it does in one line; the libraries' own chatter while it
builds the FE model for the first time (FFCx compiling DOLFINx's forms: its
``logging.basicConfig()``, then setuptools lowering the root logger to INFO
and logging every C compiler command line) is kept off the terminal, as in
every ``vibrofric`` command (cli.py).
"""

import itertools
import sys

from .friction_law.contract import BUILT_IN
from .friction_law.specialize import unannounced
from .library_logs import quiet_libraries

# The paper's Fig 7 scene (scenes/longitudinal.toml), a few cycles long.
SCENE = {
    "body": {"mass": 0.5},
    "contact": {"law": "dahl", "mu": 0.1, "F_N": 55.0, "k_t": 80e6},
    "drive": {"k_d": 96068.0, "v_d": 0.0005},
    "vibration": {"f": 4000.0, "k_v": 6.0, "theta_deg": 0.0, "t_on": 0.001},
    "time": {"T": 0.003, "dt": 1e-6, "average_cycles": 4},
    "fem": {"output_every": 0},
}
INTEGRATORS = {"explicit": 1e-6, "implicit": 1e-5, "reduced": 1e-5}   # with their time.dt
STEPPERS = {"coupled": tuple(BUILT_IN), "longitudinal": ("dahl",)}   # longitudinal: Dahl's [23]
# The steady cycle's shooting (the default, "auto") and the stepped run (its fallback, and
# "transient"): each compiles its own loops.
METHODS = ("periodic", "transient")


def warm(fe: bool = True) -> None:
    """Load or compile every built-in law's loops (and build the default FE model)."""
    from . import scene as scene_module
    from .analytic.solve import solve

    print("vibrofric: compiling the built-in friction laws' loops (" + ", ".join(BUILT_IN)
          + ") for the analytic steppers" + (" and every FE integrator, and building the "
                                             "default block's FE model" if fe else "")
          + ": once, at set-up", file=sys.stderr, flush=True)
    base = scene_module.from_dict(SCENE, "warm")
    with unannounced():
        for law, method in itertools.product(BUILT_IN, METHODS):
            scene = (base if law == "dahl" else base.with_law(law)).with_values(
                {"time.method": method})
            for stepper, laws in STEPPERS.items():
                if law in laws:
                    solve(scene, stepper, estimate=False)   # the same loops: compiled
            if fe:
                from .fem import run_fe

                for integrator, dt in INTEGRATORS.items():
                    run_fe(scene.with_values({"fem.integrator": integrator, "time.dt": dt}))


if __name__ == "__main__":
    quiet_libraries()
    warm()
