"""Record, or compare with a recording, the time series of the shipped scenes.

A restructuring of the code must leave every number as it was. Run this before
the change with ``--record FILE`` and after it with ``--compare FILE``: it runs
every shipped scene, stepped through time.T (time.method transient), with the
analytic stepper and, on the coarse mesh for 0.16 s (vibration from 0.14 s, 10
averaged cycles), with each FE integrator, and compares every recorded column
bit for bit (numpy.array_equal).

    .venv/bin/python benchmarks/same_results.py --record /tmp/before.npz
    (change the code)
    .venv/bin/python benchmarks/same_results.py --compare /tmp/before.npz

numba's compiled loops come in variants that round differently (the FE series
by up to ~1e-10 of their largest value): two fresh compiles of the same code,
with Python's hash seed unset, differed by 1e-11 in every explicit series. A
change to a compiled module recompiles it, so compare like with like: both
sides compiled fresh under one seed, e.g.

    PYTHONHASHSEED=0 NUMBA_CACHE_DIR=/tmp/before-cache .venv/bin/python ... --record ...
    PYTHONHASHSEED=0 NUMBA_CACHE_DIR=/tmp/after-cache .venv/bin/python ... --compare ...

(so compared, a restructuring of the FE loops matched 16 of 16 series bit for bit).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from vibrofric import scene as scene_module
from vibrofric.analytic.solve import solve
from vibrofric.fem import run_fe

SCENES = Path(__file__).resolve().parent.parent / "scenes"
FE_SETTINGS = {"time.T": 0.16, "time.average_cycles": 10, "fem.output_every": 0}
INTEGRATOR_STEPS = {"explicit": 1e-6, "implicit": 1e-5, "reduced": 1e-5}
# The shipped scenes are Dahl's; LuGre (a Stribeck peak and contact damping) on the Fig 7 scene too.
LUGRE = ["contact.law=\"lugre\"", "contact.F_s=6.6", "contact.v_s=0.002", "contact.h_t=50.0"]


# Stepped through time.T (time.method transient, the default before "auto"): every step of
# the time loops is compared, as in the recordings made before.
STEPPED = ['time.method="transient"']


# The paper's scenes (the other shipped scenes' bodies are not the block: their FE runs
# take other integrators and steps, docs/your-own-body.md).
PAPER_SCENES = ("coupled", "longitudinal", "transverse")


def scenes():
    for name in PAPER_SCENES:
        yield name, scene_module.load(SCENES / f"{name}.toml", STEPPED)
    yield "longitudinal-lugre", scene_module.load(SCENES / "longitudinal.toml", [*STEPPED, *LUGRE])


def series() -> dict:
    """Every time series, by name: ``<scene>/analytic`` and ``<scene>/<integrator>``."""
    out = {}
    for name, scene in scenes():
        out[f"{name}/analytic"] = solve(scene)[0].table()
        for integrator, dt in INTEGRATOR_STEPS.items():
            fe_scene = scene.with_values({**FE_SETTINGS, "fem.integrator": integrator,
                                          "time.dt": dt})
            out[f"{name}/{integrator}"] = run_fe(fe_scene).series.table()
            print(f"{name} {integrator}: {out[f'{name}/{integrator}'].shape[0]} rows",
                  file=sys.stderr)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--record", type=Path)
    action.add_argument("--compare", type=Path)
    args = parser.parse_args()
    now = series()
    if args.record:
        np.savez(args.record, **{name.replace("/", "__"): table for name, table in now.items()})
        print(f"recorded {len(now)} series in {args.record}")
        return 0
    before = np.load(args.compare)
    differ = [name for name, table in now.items()
              if not np.array_equal(before[name.replace("/", "__")], table)]
    for name in now:
        if name in differ:
            old = before[name.replace("/", "__")]
            size = old.shape == now[name].shape
            gap = np.abs(now[name] - old).max() / np.abs(old).max() if size else np.inf
            print(f"{name:28s} DIFFERS (largest difference {gap:.1e} of the largest value)")
        else:
            print(f"{name:28s} identical")
    print(f"{len(now) - len(differ)} of {len(now)} series bit-identical")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
