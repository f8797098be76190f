"""Compile at set-up, not at first use: ``python -m vibrofric.warm`` (``vibrofric warm``).

numba compiles every time loop for each friction law (friction_law/specialize.py)
and keeps what it compiled on disk. This runs a few steps of the Fig 7 scene
with each built-in law through each stepper and integrator, shot for its steady
cycle and stepped (METHODS); the same with the law called through its pointer
(friction_law/through_pointer.py: the loops a user's law runs on its first runs,
compiled once for every law); and each shipped scene (SHIPPED: its own block,
the 2 kg one of coupled and transverse, and its own motion) through each
integrator, both ways, alone and as a sweep's point (the model's arrays
read-only, a type of their own to numba). So numba's cache holds those loops and the model cache
(fem/model/model_cache.py) the shipped scenes' blocks: the first ``vibrofric
run``, ``analytic`` or ``sweep`` of a shipped scene after ``make setup`` (which
runs this) compiles nothing, and a user's law's first run compiles its update
alone, and says so.

It says what it does in one line; the libraries' own chatter while it
builds the FE model for the first time (FFCx compiling DOLFINx's forms: its
``logging.basicConfig()``, then setuptools lowering the root logger to INFO
and logging every C compiler command line) is kept off the terminal, as in
every ``vibrofric`` command (cli.py).
"""

import itertools
import sys
from pathlib import Path

from .friction_law.contract import BUILT_IN
from .friction_law.specialize import pointer_route, unannounced
from .library_logs import quiet_libraries

# The paper's Fig 7 scene (scenes/longitudinal.toml), a few cycles long: every built-in
# law's loops.
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
# Every shipped scene (vibrofric/scenes), run as it is but a few cycles long, through the
# FE integrators by both methods, alone and as a sweep's point: its own block (the 2 kg
# one of coupled and transverse: its FE model built and cached) and its own motion. (The
# ball's and the pin's through the lumped model alone: their FE models are not built
# here (the pin's, with its reduction, ~40 s), and the reduced loops they run are
# those the block's runs compile.)
SCENE_FILES = Path(__file__).resolve().parent / "scenes"
SHIPPED = ("ball", "coupled", "longitudinal", "pin", "transverse")
SHORT = {"time.T": 0.004, "vibration.t_on": 0.001, "time.average_cycles": 4,
         "fem.output_every": 0}


def warm(fe: bool = True) -> None:
    """Load or compile every built-in law's loops, those a user's law runs through on
    its first runs (friction_law/through_pointer.py), and the shipped scenes' (with
    ``fe``, their FE models built)."""
    from . import scene as scene_module
    from .analytic.solve import solve

    print("vibrofric: compiling the built-in friction laws' loops (" + ", ".join(BUILT_IN)
          + ") and those for every law, for the analytic steppers"
          + (" and every FE integrator, and building the shipped scenes' FE models" if fe
             else "") + ": once, at set-up", file=sys.stderr, flush=True)

    def run(scene, laws=BUILT_IN, as_sweep_points=False, fe=fe):
        """The scene through the steppers and (with ``fe``) every integrator, stepped and
        shot for its steady cycle, with each of ``laws``; ``as_sweep_points``: the FE runs
        once more as a sweep's points run (their shared model's arrays read-only:
        fe_model.kept_between_runs, which numba compiles loops of their own for)."""
        for law, method in itertools.product(laws, METHODS):
            with_law = (scene if law == scene.contact.law else scene.with_law(law)).with_values(
                {"time.method": method})
            for stepper, stepper_laws in STEPPERS.items():
                if law in stepper_laws:
                    solve(with_law, stepper, estimate=False)   # the same loops: compiled
            if fe:
                from .fem import run_fe
                from .fem.model.fe_model import kept_between_runs

                for integrator, dt in INTEGRATORS.items():
                    fe_scene = with_law.with_values({"fem.integrator": integrator, "time.dt": dt})
                    run_fe(fe_scene)
                    if as_sweep_points:
                        with kept_between_runs():
                            run_fe(fe_scene)

    base = scene_module.from_dict(SCENE, "warm")
    with unannounced():
        run(base)
        with pointer_route():
            run(base, ("dahl",))
        for name in SHIPPED:
            scene = scene_module.load(SCENE_FILES / f"{name}.toml").with_values(SHORT)
            run(scene, ("dahl",), as_sweep_points=True, fe=fe and _fe_runs(scene))


def _fe_runs(scene) -> bool:
    """Whether the warm-up runs the scene's FE model: the paper's block, where the FE
    model takes the scene (scene.check_fe_scene)."""
    from .scene import SceneError, check_fe_scene

    if not scene.body.is_block:
        return False
    try:
        check_fe_scene(scene)
    except SceneError:
        return False
    return True


if __name__ == "__main__":
    quiet_libraries()
    warm()
