"""The first answer's targets, whole commands timed as a user runs them (docs/first-answer.md).

From empty caches (numba's and vibrofric's, both pointed at a new directory):

    warm            python -m vibrofric.warm (what make setup runs; skipped where the
                    package has none)
    analytic        vibrofric analytic scenes/longitudinal.toml, the first after set-up
    demo            make demo's command: vibrofric run scenes/longitudinal.toml --set time.T=0.3
    fig7 reduced    vibrofric run ... fem.integrator=reduced, time.dt=1e-5, T=0.3: first, repeat
                    (time.method as the scene's default: auto, the steady cycle shot for where
                    it converges); then the same stepped through T (time.method=transient)
    user law        examples/laws/maxwell_slip.py with a constant changed, its first FE run
                    (maxwell_slip.toml, time.T=0.3) and the repeat; then with the reduced
                    integrator (time.dt=1e-5), a law edited once more: its first run compiles
                    the implicit step's contact part for it

Each line gives the goal where docs/first-answer.md sets one (GOALS, whole
command, seconds).

    python benchmarks/first_answer.py
    python benchmarks/first_answer.py --fig7 5    # only the Fig 7 repeat, 5 times each form

With ``--fig7 N`` there is no warm-up: a first run of each form compiles what it
needs (not timed), then the two forms (the scene's time.method, and transient)
run N times in turn, each line with the load average at its start.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FIG7 = ["--set", "fem.integrator=reduced", "--set", "time.dt=1e-5", "--set", "time.T=0.3"]
TRANSIENT = ["--set", "time.method=transient"]
# The targets (docs/first-answer.md), whole commands in seconds.
GOALS = {"analytic, first": 0.5, "demo, first": 10.0, "fig7 reduced, repeat": 1.0,
         "user law FE run, first": 10.0,
         "user law reduced, first": 10.0}


def timed(label: str, args, env, cwd=ROOT) -> float:
    start = time.perf_counter()
    done = subprocess.run([sys.executable, *args], env=env, cwd=cwd, capture_output=True,
                          text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{label} failed:\n{done.stderr}")
    said = [line for line in done.stderr.splitlines() if "compiling" in line]
    goal = f"goal <= {GOALS[label]:g} s" if label in GOALS else ""
    print(f"{label:30s} {seconds:7.2f} s  {goal:16s}" + (f" ({'; '.join(said)})" if said else ""),
          flush=True)
    return seconds


def fig7_repeats(times: int, cli, out, env) -> None:
    """The Fig 7 reduced repeat, as the scene sets time.method and stepped, in turn,
    ``times`` times each."""
    forms = {"fig7 reduced, repeat": FIG7, "fig7 reduced transient, repeat": [*FIG7, *TRANSIENT]}
    for settings in forms.values():   # compiles what the form needs, not timed
        subprocess.run([sys.executable, *cli, "run", "scenes/longitudinal.toml", *settings, *out],
                       env=env, cwd=ROOT, capture_output=True, check=True)
    for _ in range(times):
        for label, settings in forms.items():
            print(f"load {os.getloadavg()[0]:5.2f}  ", end="")
            timed(label, [*cli, "run", "scenes/longitudinal.toml", *settings, *out], env)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fig7", type=int, metavar="N",
                        help="only the Fig 7 reduced repeat, N times each form, no warm-up")
    args = parser.parse_args()
    cpu = next((line.split(":", 1)[1].strip() for line in
                Path("/proc/cpuinfo").read_text().splitlines() if line.startswith("model name")),
               "unknown")
    print(f"machine: {cpu}, load average {os.getloadavg()[0]:.2f}", flush=True)
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        env = {**os.environ, "NUMBA_CACHE_DIR": str(scratch / "numba"),
               "VIBROFRIC_CACHE": str(scratch / "cache"),
               "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
        # gmsh's .msh file, cached since before: made beforehand, not measured
        subprocess.run([sys.executable, "-c", "from vibrofric.meshes import block_mesh_file; "
                        "block_mesh_file()"], env=env, cwd=ROOT, check=True)
        cli = ["-m", "vibrofric.cli"]
        out = ["--out", str(scratch / "out"), "--force"]
        if args.fig7:
            fig7_repeats(args.fig7, cli, out, env)
            print(f"load average after: {os.getloadavg()[0]:.2f}")
            return
        if (ROOT / "vibrofric" / "warm.py").exists():
            timed("warm (make setup)", ["-m", "vibrofric.warm"], env)
        timed("analytic, first", [*cli, "analytic", "scenes/longitudinal.toml", *out], env)
        timed("analytic, repeat", [*cli, "analytic", "scenes/longitudinal.toml", *out], env)
        timed("demo, first", [*cli, "run", "scenes/longitudinal.toml", "--set", "time.T=0.3", *out],
              env)
        timed("demo, repeat", [*cli, "run", "scenes/longitudinal.toml", "--set", "time.T=0.3",
                               *out], env)
        timed("fig7 reduced, first", [*cli, "run", "scenes/longitudinal.toml", *FIG7, *out], env)
        timed("fig7 reduced, repeat", [*cli, "run", "scenes/longitudinal.toml", *FIG7, *out], env)
        stepped = [*cli, "run", "scenes/longitudinal.toml", *FIG7, *TRANSIENT, *out]
        timed("fig7 reduced transient, first", stepped, env)
        timed("fig7 reduced transient, repeat", stepped, env)
        law = (ROOT / "examples" / "laws" / "maxwell_slip.py").read_text()
        edited = law.replace("ELEMENTS = 4", "ELEMENTS = 3", 1)
        assert edited != law
        (scratch / "maxwell_slip.py").write_text(edited)
        (scratch / "maxwell_slip.toml").write_text(
            (ROOT / "examples" / "laws" / "maxwell_slip.toml").read_text())
        scene = str(scratch / "maxwell_slip.toml")
        timed("user law FE run, first", [*cli, "run", scene, "--set", "time.T=0.3", *out], env)
        timed("user law FE run, repeat", [*cli, "run", scene, "--set", "time.T=0.3", *out], env)
        (scratch / "maxwell_slip.py").write_text(law.replace("ELEMENTS = 4", "ELEMENTS = 2", 1))
        reduced = ["--set", "fem.integrator=reduced", "--set", "time.dt=1e-5", "--set", "time.T=0.3"]
        timed("user law reduced, first", [*cli, "run", scene, *reduced, *out], env)
        timed("user law reduced, repeat", [*cli, "run", scene, *reduced, *out], env)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
