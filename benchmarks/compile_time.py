"""Where numba's compile time goes: per friction law and integrator, on a cold cache.

Each case runs in a fresh process with an empty numba cache (NUMBA_CACHE_DIR
pointed at a new directory): a few steps of the Fig 7 scene (scenes/longitudinal.toml)
with the law and the integrator, timing every function numba compiles on the
way (numba's "numba:compile" events; a function's time includes the functions
it calls that were compiled inside it). Then the same case again in a second
process on the cache the first one left: what a run pays once the cache is warm.

    python benchmarks/compile_time.py                  all cases
    python benchmarks/compile_time.py dahl:reduced     some of them (law:integrator;
                                                       integrators explicit, implicit,
                                                       reduced, coupled, longitudinal)

The user law is examples/laws/maxwell_slip.py with one constant changed (a law
numba has never seen). Results: docs/first-answer.md.
"""

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = [f"{law}:{integrator}" for law in ("dahl", "lugre", "user")
         for integrator in ("coupled", "explicit", "implicit", "reduced")] + ["dahl:longitudinal"]
SHORT = {"time.T": 0.003, "vibration.t_on": 0.001, "time.average_cycles": 4}  # a few cycles: the run costs next to nothing


def user_law(directory: Path) -> Path:
    """maxwell_slip.py with its element count changed: source numba has not compiled."""
    text = (ROOT / "examples" / "laws" / "maxwell_slip.py").read_text()
    changed = text.replace("ELEMENTS = 4", "ELEMENTS = 5", 1)
    assert changed != text, "maxwell_slip.py no longer sets ELEMENTS = 4"
    path = directory / "maxwell_slip_edited.py"
    path.write_text(changed)
    return path


def run_case(case: str, law_file: str) -> dict:
    """In this process: the case's run, with numba's compile events timed."""
    from numba.core import event

    from vibrofric import scene as scene_module

    law, integrator = case.split(":")
    start = time.perf_counter()
    scene = scene_module.load(ROOT / "scenes" / "longitudinal.toml")
    if law != "dahl":
        scene = scene.with_law(law_file if law == "user" else law)
    values = dict(SHORT)
    if integrator in ("implicit", "reduced"):
        values["time.dt"] = 1e-5
    if integrator in ("explicit", "implicit", "reduced"):
        values["fem.integrator"] = integrator
        values["fem.output_every"] = 0
    scene = scene.with_values(values)
    timings, depth = {}, [0]

    class Timer(event.Listener):
        def on_start(self, ev):
            ev.data["started"] = time.perf_counter()
            ev.data["depth"] = depth[0]
            depth[0] += 1

        def on_end(self, ev):
            depth[0] -= 1
            name = ev.data["dispatcher"].py_func.__qualname__.split("__")[0]
            spent = time.perf_counter() - ev.data["started"]
            entry = timings.setdefault(name, {"seconds": 0.0, "top": ev.data["depth"] == 0})
            entry["seconds"] += spent

    listener = Timer()
    event.register("numba:compile", listener)
    try:
        before = time.perf_counter()
        if integrator in ("coupled", "longitudinal"):
            from vibrofric.analytic.solve import solve

            solve(scene, integrator)
        else:
            from vibrofric.fem import run_fe

            run_fe(scene)
        run_time = time.perf_counter() - before
    finally:
        event.unregister("numba:compile", listener)
    compile_time = sum(entry["seconds"] for entry in timings.values() if entry["top"])
    return {"case": case, "compile_s": compile_time, "run_s": run_time,
            "process_s": time.perf_counter() - start,
            "functions": {name: round(entry["seconds"], 2) for name, entry in
                          sorted(timings.items(), key=lambda item: -item[1]["seconds"])}}


def in_fresh_process(case: str, law_file: Path, cache: Path) -> dict:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache),
           "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    started = time.perf_counter()
    done = subprocess.run([sys.executable, __file__, "--child", case, str(law_file)], env=env,
                          capture_output=True, text=True, check=True)
    result = json.loads(done.stdout.strip().splitlines()[-1])
    result["command_s"] = time.perf_counter() - started
    return result


def main(cases) -> None:
    print(f"machine: {machine()}", flush=True)
    with tempfile.TemporaryDirectory() as scratch:
        law_file = user_law(Path(scratch))
        for case in cases:
            cache = Path(scratch) / f"numba-{case.replace(':', '-')}"
            cold = in_fresh_process(case, law_file, cache)
            warm = in_fresh_process(case, law_file, cache)
            top = ", ".join(f"{name} {seconds:.1f}" for name, seconds in cold["functions"].items()
                            if seconds >= 0.5)
            print(f"{case:20s} compile {cold['compile_s']:6.1f} s  process cold "
                  f"{cold['command_s']:6.1f} s, warm {warm['command_s']:5.1f} s  [{top}]",
                  flush=True)


def machine() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return "unknown"


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        print(json.dumps(run_case(sys.argv[2], sys.argv[3])))
    else:
        main(sys.argv[1:] or CASES)
