"""The reduction's error estimate (fem/integrators/reduction.py, compliance_error): the
full model's compliances from one real factorization and its Krylov space
(FullCompliance) against the complex LU at each compared harmonic (direct_compliance),
on the blocks and the balls (docs/performance.md, "2026-11-27: the reduction's error
estimate from one real factorization").

For each case, in this process (over the model cache VIBROFRIC_CACHE says, whose
reductions it reuses and whose compliance entries it does not touch):

    krylov s    FullCompliance at the scene's compared harmonics (its factorization and
                space), and its size (vectors)
    direct s    direct_compliance at each of them (a complex LU each)
    estimates   max_p |c_red - c_full| / |c(0)| per harmonic, by each
    agreement   max over harmonics and loads of |c_krylov - c_direct| / |c(0)|, and the
                largest relative difference of the two estimates' per-harmonic values

The cases: "block-coarse", "block-fine" (scenes/longitudinal.toml at fem.mesh coarse,
fine), "ball-coarse", "ball-fine" (scenes/ball.toml at coarse, fine; the interface
fem.interface_reach = 3, or every candidate with a "-all" suffix), "ball-50k" (fine with
refinement.BODY_DIVISIONS["fine"] = 16, as benchmarks/fe_body_scaling.py's case; run it
in a process of its own, since that setting stays).

    PYTHONPATH=. python benchmarks/reduction_estimate.py ball-coarse-all block-coarse ...
        [--no-direct]

prints one JSON line per case.
"""

import argparse
import json
import math
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = {"block": "scenes/longitudinal.toml", "ball": "scenes/ball.toml"}


def measure(case: str, direct: bool) -> dict:
    import numpy as np

    from vibrofric import scene as scenes
    from vibrofric.fem.integrators import reduction
    from vibrofric.fem.integrators.interface import Interface
    from vibrofric.fem.model import fe_model
    from vibrofric.meshes import refinement

    body, level, *rest = case.split("-")
    if level == "50k":
        refinement.BODY_DIVISIONS["fine"] = 16
        level = "fine"
    reach = "all" if rest == ["all"] or body == "block" else 3.0
    scene = scenes.load(ROOT / SCENES[body]).with_values({"fem.mesh": level})
    model = fe_model.build_model(scene, None)
    interface = Interface.of(model, reach)
    inner = interface.model(model)
    kept = reduction.reduced(inner, scene.fem.cutoff * scene.vibration.f,
                             interface.watched_dofs(model), interface.digest())
    k_t = scene.law_bounds.stiffness
    omegas = [2.0 * math.pi * h * scene.vibration.f for h in reduction.compared_harmonics(scene)]
    static = np.abs(reduction._reduced_compliance(inner, kept, k_t, 0.0))

    def estimates(full):
        return [float(np.max(np.abs(reduction._reduced_compliance(inner, kept, k_t, w)
                                    - full[w]) / static)) for w in omegas]

    out = {"case": case, "dofs": model.dofs, "candidates": int(model.contact_nodes.size),
           "patch": int(model.in_contact0.sum()), "interface": int(interface.kept.size)}
    start = time.perf_counter()
    solver = reduction.FullCompliance(inner, kept.boundary, k_t, omegas)
    krylov = {w: solver.at(w) for w in omegas}
    out.update(krylov_s=time.perf_counter() - start, krylov_size=solver.size,
               settled=solver.settled, krylov_estimates=estimates(krylov))
    if direct:
        start = time.perf_counter()
        exact = {w: reduction.direct_compliance(inner, kept.boundary, k_t, w) for w in omegas}
        out.update(direct_s=time.perf_counter() - start, direct_estimates=estimates(exact))
        out["agreement"] = max(float(np.max(np.abs(krylov[w] - exact[w]) / static))
                               for w in omegas)
        out["estimate_difference"] = max(abs(a / b - 1.0) for a, b in
                                         zip(out["krylov_estimates"], out["direct_estimates"]))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="+")
    parser.add_argument("--no-direct", action="store_true")
    args = parser.parse_args()
    for case in args.cases:
        print(json.dumps(measure(case, not args.no_direct)), flush=True)


if __name__ == "__main__":
    main()
