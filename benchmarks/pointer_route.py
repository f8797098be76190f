"""A law through its pointer against the same law linked into the loops: bits and speed.

A user's law's first runs call it through a function pointer (through_pointer.py),
its later runs through the loops specialized for it (specialize.py). This runs one
scene both ways in one process, in turn (``--repeats`` times each, so that the
load of a shared machine falls on both alike), and prints for each model

- the largest difference of each series' column between the two routes, relative
  to the column's largest value, and of F_dv/F_d0;
- the time of the run itself (the FE model: its time loop or shooting,
  ``loop_time_s``; the analytic stepper: its wall time), smallest of the repeats.

Both routes are compiled (or loaded) before the first timed run.

    PYTHONPATH=. python benchmarks/pointer_route.py [--law examples/laws/jenkins.py]
        [--integrator reduced] [--method transient] [--T 0.3] [--repeats 3]
"""

import argparse
import time

import numpy as np

from vibrofric import scene as scene_module
from vibrofric.analytic.solve import solve
from vibrofric.analytic.summary import summarize
from vibrofric.fem import run_fe
from vibrofric.friction_law.specialize import pointer_route


def runs(scene, integrator: str):
    """{model: (series, seconds)} for the analytic stepper and the FE integrator."""
    started = time.perf_counter()
    analytic, _ = solve(scene, "coupled")
    analytic_s = time.perf_counter() - started
    fe = run_fe(scene.with_values({"fem.integrator": integrator}))
    return {"analytic": (analytic, analytic_s), "FE": (fe.series, fe.info["loop_time_s"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--law", default="examples/laws/jenkins.py")
    parser.add_argument("--scene", default="scenes/longitudinal.toml")
    parser.add_argument("--integrator", default="reduced")
    parser.add_argument("--method", default="transient")
    parser.add_argument("--dt", type=float, default=1e-5)
    parser.add_argument("--T", type=float, default=0.3)
    parser.add_argument("--repeats", type=int, default=3)
    options = parser.parse_args()
    scene = scene_module.load(options.scene).with_values({
        "contact.law": options.law, "time.method": options.method, "time.dt": options.dt,
        "time.T": options.T, "fem.output_every": 0})

    seconds = {"pointer": {}, "linked": {}}
    results = {}
    for repeat in range(options.repeats + 1):       # the first: compile or load, untimed
        for route in ("pointer", "linked"):
            if route == "pointer":
                with pointer_route():
                    done = runs(scene, options.integrator)
            else:
                done = runs(scene, options.integrator)
            results[route] = done
            if repeat:
                for model, (_, took) in done.items():
                    seconds[route].setdefault(model, []).append(took)

    print(f"{options.law}, {options.scene}, {options.integrator}, {options.method}, "
          f"dt {options.dt:g}, T {options.T:g}")
    for model in ("analytic", "FE"):
        pointer, linked = results["pointer"][model][0], results["linked"][model][0]
        a, b = pointer.table(), linked.table()
        if a.shape != b.shape:
            print(f"{model}: {a.shape[0]} rows through the pointer, {b.shape[0]} linked")
            continue
        scale = np.maximum(np.max(np.abs(b), axis=0), np.finfo(float).tiny)
        columns = np.max(np.abs(a - b), axis=0) / scale
        ratio = [summarize(s, scene, 0.0)["F_dv_over_F_d0"] for s in (pointer, linked)]
        print(f"{model}: identical {np.array_equal(a, b)}; largest difference per column "
              f"(of its largest value) {np.array2string(columns, precision=2)}; "
              f"F_dv/F_d0 {ratio[0]!r} / {ratio[1]!r}; time pointer "
              f"{min(seconds['pointer'][model]):.3f} s, linked "
              f"{min(seconds['linked'][model]):.3f} s")


if __name__ == "__main__":
    main()
