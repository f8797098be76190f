"""How the FE model's set-up and step grow with DOFs and contact candidates: the ball
refined at its contact beside the paper's block, at about 20k, 50k and 100k DOFs
(docs/performance.md, "2026-11-27: the FE ball and block from 20k to 100k DOFs";
the 50k ball's basis read apart, "2026-11-27: the cached reduction without its basis";
its interface limited, "2026-11-27: the reduced model's interface limited to the
candidates within reach").

The ball is scenes/ball.toml's at fem.mesh = "fine" (its Hertz patch resolved by
refinement.PATCH_ELEMENTS["fine"] elements across its radius), with the element edge
away from the contact set by refinement.BODY_DIVISIONS["fine"] = the case's divisions
(12 is the shipped "fine" level; 16 and 21 are not levels of the package: this script
sets them in its own process, over a mesh cache of its own). The block is
scenes/longitudinal.toml at element counts "NXxNYxNZ" (16x20x28 is its "fine" level).

Each case runs twice, each time in a fresh process (so that its peak resident memory,
resource.getrusage's ru_maxrss, is that run's): "first", over an empty cache
directory (VIBROFRIC_CACHE: meshes and the model cache), then "cached", over the
cache the first left. Each process times

    mesh        meshes.body_mesh (gmsh; from the cache: reading and checking the file)
    assembly    model_cache.body (DOLFINx's assembly; from the cache: the arrays read)
    preload     preload.static_preload (the contact patch and u0)
    frequency   stability.max_frequency (the explicit stable step)
    set-up      fe_model.build_model whole (the above and the rest)
    reduction   the reduced integrator's set-up (reduction.reduced: constraint and
                fixed-interface modes, the projected matrices) on the interface that
                fem.interface_reach keeps (integrators/interface.py; --interface-reach,
                default the scene's), its error estimate apart
    basis       the reduction's basis first asked for (Reduction.basis: from the cache,
                its file mapped and checked), as a run's frames and last fields ask
    a step      of each integrator: explicit at 0.9 of the model's stable step, implicit
                and reduced at IMPLICIT_DT or, where their contact iteration refuses it
                (core.errors.StepTooLong), just below the step it names; STEPS steps
                timed after WARM_STEPS (which take numba's compiling, if any)

and the counts: DOFs, contact candidates, nodes in the preload's patch, the
interface's nodes.

    PYTHONPATH=. python benchmarks/fe_body_scaling.py [--cases ball-20k,block-20k,...]
        [--interface-reach 3|all] [--out results/body_scaling.json]

prints a Markdown table and the fitted exponents p of time ~ DOFs^p per body. The
100k ball took 5 min and peaked at 10.6 GB (its first run's reduction): run it once.
"""

import argparse
import json
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# name: (body, scene file, fem.mesh, the ball's body divisions or None, the integrators
# whose step is timed). The ball's implicit integrator is left out: its set-up (the
# contact space, a column of A^-1 for each of the 1,692 candidate DOFs, solve by solve)
# ran more than 6 min on the 20k ball without reaching its first step.
ALL = ("explicit", "implicit", "reduced")
CASES = {
    "ball-20k": ("ball", "scenes/ball.toml", "fine", 12, ("explicit", "reduced")),
    "ball-50k": ("ball", "scenes/ball.toml", "fine", 16, ("explicit", "reduced")),
    "ball-100k": ("ball", "scenes/ball.toml", "fine", 21, ("explicit", "reduced")),
    "block-20k": ("block", "scenes/longitudinal.toml", "14x17x24", None, ALL),
    "block-50k": ("block", "scenes/longitudinal.toml", "19x24x33", None, ALL),
    "block-100k": ("block", "scenes/longitudinal.toml", "24x30x42", None, ALL),
}
DEFAULT_CASES = ("ball-20k", "block-20k", "ball-50k", "block-50k")
# The cases whose reduction error estimate (one real factorization of the whole model and
# its Krylov space, reduction.FullCompliance) is timed; the others' is left out.
ERROR_CASES = ("ball-20k", "block-20k", "ball-50k")

STEPS = 300          # steps timed per integrator
WARM_STEPS = 20      # steps run first (the loop's first call loads its compiled code)
IMPLICIT_DT = 1e-5   # s: the bench's implicit and reduced step (25 a 4 kHz cycle)


def _timed(module, name, clock: dict, label: str):
    """Wrap module.name so that its calls' wall time adds up in clock[label]."""
    original = getattr(module, name)

    def wrapper(*args, **kwargs):
        start = time.perf_counter()
        try:
            return original(*args, **kwargs)
        finally:
            clock[label] = clock.get(label, 0.0) + time.perf_counter() - start

    setattr(module, name, wrapper)


def _step_seconds(run) -> float:
    """Seconds a step of a prepared integrator: STEPS steps after WARM_STEPS."""
    from vibrofric.core.series import RecordPlan

    run.integrate(RecordPlan(WARM_STEPS, WARM_STEPS, 1))   # every row in the ring
    start = time.perf_counter()
    run.integrate(RecordPlan(STEPS, STEPS, 1))
    return (time.perf_counter() - start) / STEPS


def _note(case, clock) -> None:
    print(f"{case}: " + ", ".join(f"{k} {v:.3g} s" for k, v in clock.items()),
          file=sys.stderr, flush=True)


def _prepared(scene, model, integrator: str, dt: float, kept) -> tuple:
    """(the prepared integrator, its step) at ``dt``, or at the longest step its contact
    iteration takes where it refuses ``dt`` (core.errors.StepTooLong names it): a step's
    cost hardly depends on its length, and the step a body needs is another question
    (docs/performance.md)."""
    from vibrofric.core.errors import StepTooLong
    from vibrofric.fem.integrators import reduction, registry

    case = scene.with_values({"fem.integrator": integrator, "time.dt": dt})
    try:
        if integrator == "reduced":   # the reduction made, its error estimate left out
            return reduction.ImplicitRun(case, model, kept.system(), name="reduced"), dt
        return registry.select(case)(case, model), dt
    except StepTooLong as refusal:
        match = re.search(r"time\.dt <= ([0-9.eE+-]+)", str(refusal))
        if match is None or float(match.group(1)) >= dt:
            raise
        return _prepared(scene, model, integrator, 0.99 * float(match.group(1)), kept)


def measure(case: str, steps: bool, reach) -> dict:
    """One process's measurements of ``case`` (module docstring), its interface that of
    fem.interface_reach ``reach`` (None: the scene's)."""
    body, scene_file, level, divisions, integrators = CASES[case]
    from mpi4py import MPI

    from vibrofric import meshes
    from vibrofric.api import load_scene
    from vibrofric.fem.integrators import reduction
    from vibrofric.fem.integrators.interface import Interface
    from vibrofric.fem.model import fe_model, model_cache
    from vibrofric.meshes import refinement

    if divisions is not None:
        refinement.BODY_DIVISIONS["fine"] = divisions
    clock = {}
    _timed(meshes, "body_mesh", clock, "mesh")
    _timed(model_cache, "body", clock, "assembly")
    _timed(fe_model, "static_preload", clock, "preload")
    _timed(fe_model.stability, "max_frequency", clock, "frequency")
    scene = load_scene(ROOT / scene_file).with_values(
        {"fem.mesh": level, "vibration.t_on": 0.0,
         **({} if reach is None else {"fem.interface_reach": reach})})
    start = time.perf_counter()
    model = fe_model.build_model(scene, MPI.COMM_SELF)
    clock["setup"] = time.perf_counter() - start

    _note(case, clock)
    start = time.perf_counter()
    interface = Interface.of(model, scene.fem.interface_reach)
    full_model, model = model, interface.model(model)   # as reduction.ReducedRun does
    kept = reduction.reduced(model, scene.fem.cutoff * scene.vibration.f,
                             interface.watched_dofs(full_model), interface.digest())
    clock["reduction"] = time.perf_counter() - start
    start = time.perf_counter()
    kept.basis
    clock["basis"] = time.perf_counter() - start
    if case in ERROR_CASES:
        start = time.perf_counter()
        reduction.compliance_error(model, kept, scene)
        clock["reduction_error"] = time.perf_counter() - start
    _note(case, clock)
    out = {"case": case, "body": body, "level": level, "divisions": divisions,
           "dofs": model.dofs, "candidates": int(full_model.contact_nodes.size),
           "patch": int(model.in_contact0.sum()), "interface": int(interface.kept.size),
           "dt_stable": model.dt_stable,
           "reduced_size": int(kept.mass.shape[0]), "seconds": clock}
    if steps:
        step, step_dt = {}, {}
        for name in integrators:
            dt = 0.9 * model.dt_stable if name == "explicit" else IMPLICIT_DT
            prepared, step_dt[name] = _prepared(scene, model, name, dt, kept)
            step[name] = _step_seconds(prepared)
            print(f"{case}: {name} step {step[name]:.3g} s at dt {step_dt[name]:.3g} s",
                  file=sys.stderr, flush=True)
        out["step_seconds"], out["step_dt"] = step, step_dt
    reduction.forget()
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    return out


def run_case(case: str, cache: Path, steps: bool, reach=None) -> dict:
    """measure(case) in a fresh process over the cache directory ``cache``."""
    env = {**os.environ, "VIBROFRIC_CACHE": str(cache),
           "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    command = [sys.executable, __file__, "--child", case] + ([] if steps else ["--no-steps"])
    if reach is not None:
        command += ["--interface-reach", str(reach)]
    start = time.perf_counter()
    done = subprocess.run(command, env=env, stdout=subprocess.PIPE, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{case}: exit {done.returncode}")
    result = json.loads(done.stdout.strip().splitlines()[-1])
    result["process_seconds"] = time.perf_counter() - start
    return result


def _reach(text: str):
    return text if text == "all" else float(text)


def fit_exponent(x, y) -> float:
    """p of y ~ x^p, least squares in log-log."""
    import numpy as np

    if len(x) < 2:
        return math.nan
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def table(results: list) -> str:
    rows = ["| case | DOFs | candidates (patch) | reduced size (interface) | run | mesh s | assembly s | "
            "preload s | frequency s | set-up s | reduction s (+ error s) | basis s | "
            "explicit step ms | implicit step ms | reduced step ms | their step s | peak RSS MB |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        s, step = r["seconds"], r.get("step_seconds", {})

        def ms(name):
            return f"{1e3 * step[name]:.3g}" if name in step else "-"

        dts = r.get("step_dt", {})
        implicit_dt = ", ".join(f"{dts[n]:.2g}" for n in ("implicit", "reduced") if n in dts) or "-"
        error = s.get("reduction_error")
        rows.append(
            f"| {r['case']} ({r['level']}{'' if r['divisions'] is None else ', ' + str(r['divisions']) + ' divisions'}) "
            f"| {r['dofs']:,} | {r['candidates']} ({r['patch']}) | "
            f"{r['reduced_size']} ({r.get('interface', r['candidates'])}) | {r['run']} "
            f"| {s.get('mesh', 0):.3g} | {s.get('assembly', 0):.3g} | {s.get('preload', 0):.3g} "
            f"| {s.get('frequency', 0):.3g} | {s['setup']:.3g} "
            f"| {s['reduction']:.3g} ({'-' if error is None else f'+{error:.3g}'}) "
            f"| {s['basis']:.3g} | {ms('explicit')} "
            f"| {ms('implicit')} | {ms('reduced')} | {implicit_dt} | {r['peak_rss_mb']:.0f} |")
    return "\n".join(rows)


def exponents(results: list) -> str:
    lines = ["| body | run | quantity | fitted p (time ~ DOFs^p) |", "|---|---|---|---|"]
    for body in ("ball", "block"):
        for run in ("first", "cached"):
            chosen = sorted((r for r in results if r["body"] == body and r["run"] == run),
                            key=lambda r: r["dofs"])
            if len(chosen) < 2:
                continue
            dofs = [r["dofs"] for r in chosen]
            quantities = [("set-up", [r["seconds"]["setup"] for r in chosen]),
                          ("reduction", [r["seconds"]["reduction"] for r in chosen])]
            for name in ("explicit", "implicit", "reduced"):
                if all(name in r.get("step_seconds", {}) for r in chosen):
                    quantities.append((f"{name} step", [r["step_seconds"][name] for r in chosen]))
            for name, values in quantities:
                lines.append(f"| {body} | {run} | {name} | {fit_exponent(dofs, values):.2f} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default=",".join(DEFAULT_CASES),
                        help=f"comma-separated, of {', '.join(CASES)}")
    parser.add_argument("--out", type=Path, help="also write the results as JSON")
    parser.add_argument("--interface-reach", type=_reach,
                        help="fem.interface_reach: a number > 0 or \"all\" (default: the scene's)")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--no-steps", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.child, not args.no_steps, args.interface_reach)))
        return
    results = []
    for case in args.cases.split(","):
        if case not in CASES:
            parser.error(f"--cases: {case!r} is not one of {', '.join(CASES)}")
    for case in args.cases.split(","):
        with tempfile.TemporaryDirectory(prefix="vibrofric-scaling-") as cache:
            for run, steps in (("first", False), ("cached", True)):
                result = run_case(case, Path(cache), steps, args.interface_reach)
                result["run"] = run
                results.append(result)
                print(f"{case} {run}: set-up {result['seconds']['setup']:.3g} s, "
                      f"{result['process_seconds']:.3g} s in all", file=sys.stderr, flush=True)
                if args.out:
                    args.out.parent.mkdir(parents=True, exist_ok=True)
                    args.out.write_text(json.dumps(results, indent=1))
    print(table(results))
    print()
    print(exponents(results))


if __name__ == "__main__":
    main()
