"""The FE answer's cost with the base moving along Z against the in-plane scene's.

The longitudinal scene on the coarse block, by one integrator, once with the base in
its plane alone and once also along Z (vibration.normal_amplitude, in contact), each
run ``--repeats`` times after a first run that compiles; the best loop time of each
(a steady cycle's: its solver's time, fem/simulate.py), and their ratio (the
target: under 2). ``--method transient`` (the default here) steps through 5 ms of
sliding and 25 ms of vibration; ``--method auto`` (the scene's default) answers by
the steady cycle ending at the same 30 ms (integrators/periodic.py), and says
whether each run found it.

    .venv/bin/python benchmarks/fe_normal_speed.py [--integrator explicit] [--repeats 3]
        [--method transient|auto]
"""

import argparse
import platform

from vibrofric.api import load_scene
from vibrofric.fem import run_fe


def scene(integrator: str, amplitude: float, method: str = "transient"):
    values = {"vibration.t_on": 0.005, "time.T": 0.03, "time.average_cycles": 20,
              "time.method": method, "time.error_estimate": False,
              "fem.integrator": integrator, "fem.output_every": 0}
    if integrator != "explicit":
        values["time.dt"] = 5e-6
    if amplitude > 0.0:
        values["vibration.normal_amplitude"] = amplitude
    return load_scene("longitudinal", **values)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--integrator", default="explicit")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--amplitude", type=float, default=5e-8)
    parser.add_argument("--method", default="transient", choices=("transient", "auto"))
    args = parser.parse_args()
    best, answered = {}, {}
    for amplitude in (0.0, args.amplitude):
        s = scene(args.integrator, amplitude, args.method)
        run_fe(s)                      # compiles
        runs = [run_fe(s).info for _ in range(args.repeats)]
        best[amplitude] = min(info["loop_time_s"] for info in runs)
        answered[amplitude] = {(info.get("periodic") or {}).get("method", "stepped")
                               for info in runs}
    in_plane, normal = best[0.0], best[args.amplitude]
    print(f"{args.integrator}, coarse, time.method {args.method}, "
          f"{scene(args.integrator, 0.0).steps} steps planned ({platform.node()}): in-plane "
          f"{in_plane:.3f} s ({'/'.join(sorted(answered[0.0]))}), with A_n = "
          f"{args.amplitude:g} m {normal:.3f} s ({'/'.join(sorted(answered[args.amplitude]))}), "
          f"ratio {normal / in_plane:.2f}")


if __name__ == "__main__":
    main()
