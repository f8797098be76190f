"""The FE answer's cost with the base moving along Z against the in-plane scene's.

The longitudinal scene on the coarse block, stepped (time.method transient) through
5 ms of sliding and 25 ms of vibration by one integrator, once with the base in its
plane alone and once also along Z (vibration.normal_amplitude, in contact), each run
``--repeats`` times after a first run that compiles; the best loop time of each, and
their ratio (the target: under 2).

    .venv/bin/python benchmarks/fe_normal_speed.py [--integrator explicit] [--repeats 3]
"""

import argparse
import platform

from vibrofric.api import load_scene
from vibrofric.fem import run_fe


def scene(integrator: str, amplitude: float):
    values = {"vibration.t_on": 0.005, "time.T": 0.03, "time.average_cycles": 20,
              "time.method": "transient", "time.error_estimate": False,
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
    args = parser.parse_args()
    best = {}
    for amplitude in (0.0, args.amplitude):
        s = scene(args.integrator, amplitude)
        run_fe(s)                      # compiles
        best[amplitude] = min(run_fe(s).info["loop_time_s"] for _ in range(args.repeats))
    in_plane, normal = best[0.0], best[args.amplitude]
    print(f"{args.integrator}, coarse, {scene(args.integrator, 0.0).steps} steps "
          f"({platform.node()}): in-plane {in_plane:.3f} s, with A_n = {args.amplitude:g} m "
          f"{normal:.3f} s, ratio {normal / in_plane:.2f}")


if __name__ == "__main__":
    main()
