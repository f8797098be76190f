"""How fast the analytic steppers are, and what scipy's solve_ivp costs for the same answer.

Three measurements on this machine, printed as Markdown tables:

1. Stepper time: one 1 s scene at dt = 1e-6 (10^6 steps) through the numba
   stepper after compilation is cached (one warm-up call, then the best of N).
   Target: at most 50 ms.
2. The whole Fig 12 sweep (5 k_v x 25 angles, each 1 s at dt = 1e-6) on two
   workers, wall time including the process pool start. Target: at most 10 s.
3. Error against time on the longitudinal case (k_v = 6): our coupled stepper
   at several dt, and the same 1D Dahl model written as an ODE for
   scipy.integrate.solve_ivp at several tolerances, both measured against one
   converged reference; then, at equal error, how much faster ours is.
   Target: at least 100x.

    PYTHONPATH=. python benchmarks/analytic_speed.py [--quick] [--out DIR]

--out DIR also writes DIR/analytic_speed.md and the log-log plot
DIR/analytic_speed.png. The full run takes about 3 minutes, --quick under one.
"""

import argparse
import math
import os
import platform
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np
import scipy
from scipy.integrate import solve_ivp

from vibrofric import scene as scene_module
from vibrofric.analytic.solve import STEPPERS, solve
from vibrofric.analytic.summary import summarize
from vibrofric.batch import sweep

SCENES = Path(__file__).resolve().parent.parent / "scenes"
STEP_DT = 1e-6                  # s: the paper's step, 10^6 steps per 1 s scene
STEPPER_TARGET_S = 0.050
SWEEP_TARGET_S = 10.0
SPEEDUP_TARGET = 100.0
FIG12_GRID = [("vibration.k_v", [2.0, 3.0, 4.0, 6.0, 20.0]),
              ("vibration.theta_deg", [float(v) for v in np.linspace(0.0, 360.0, 25)])]
CONVERGENCE_DTS = (4e-6, 2e-6, 1e-6, 5e-7)
SOLVE_CAP_S = 120.0             # s: a solve_ivp run still going after this is abandoned
LADDER_STOP_S = 20.0            # s: a method's tolerances stop tightening after a solve this long
POINTS_PER_CYCLE = 200          # solve_ivp samples of F_d per vibration cycle in the final window
# Typical sizes of the ODE state (x, v, s): atol = rtol * these, s on the sliding length s_c.
X_SCALE, V_SCALE = 1e-4, 1e-3   # m, m/s


@dataclass(frozen=True)
class Plan:
    """What one run measures: the full set, or the reduced one of --quick."""

    repeats: int                # timed calls of a stepper after the warm-up, best kept
    reference_dt: float         # s: dt of the exact-update 1D stepper taken as converged
    methods: tuple              # solve_ivp methods
    rtols: tuple                # tried loose to tight, until the error reaches our stepper's
    tight: tuple                # (method, rtol) of the tight solve checking the reference


FULL = Plan(repeats=5, reference_dt=1e-8, methods=("RK45", "DOP853", "LSODA", "Radau"),
            rtols=(1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7),
            tight=("LSODA", 1e-9))
QUICK = Plan(repeats=2, reference_dt=5e-8, methods=("RK45", "LSODA"),
             rtols=(1e-2, 1e-3, 1e-5), tight=("LSODA", 1e-7))


def load(name: str, **values):
    """A shipped scene with ``{"section.key": value}`` overrides (keys spelled with __)."""
    scene = scene_module.load(SCENES / f"{name}.toml")
    return scene.with_values({key.replace("__", "."): v for key, v in values.items()})


def note(text: str) -> None:
    """Progress on stderr, so that stdout stays the Markdown report."""
    print(text, file=sys.stderr, flush=True)


# --- 1. stepper time --------------------------------------------------------------------------

def timed_stepper(scene, stepper: str, repeats: int):
    """(best seconds of the stepper call, F_dv/F_d0): one warm-up call, then ``repeats`` timed.

    The warm-up compiles the numba loop or loads it from numba's cache; the
    time is of the stepper call alone (loop, recording, series), not the summary.
    """
    step = STEPPERS[stepper]
    series = step(scene)
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        series = step(scene)
        best = min(best, time.perf_counter() - start)
    return best, summarize(series, scene, best)["F_dv_over_F_d0"]


def stepper_speed(plan: Plan) -> list:
    """Each shipped scene at dt = 1e-6 through the coupled stepper, both updates; and the 1D one."""
    cases = [(name, "coupled", update) for name in ("coupled", "longitudinal", "transverse")
             for update in ("paper", "exact")]
    cases += [("longitudinal", "longitudinal", update) for update in ("paper", "exact")]
    rows = []
    for name, stepper, update in cases:
        scene = load(name, time__dt=STEP_DT, contact__update=update)
        seconds, ratio = timed_stepper(scene, stepper, plan.repeats)
        note(f"stepper {name} {stepper} {update}: {seconds * 1e3:.1f} ms")
        rows.append([name, f"{scene.vibration.theta_deg:g}", stepper, update,
                     f"{seconds * 1e3:.1f}", yes_no(seconds <= STEPPER_TARGET_S), f"{ratio:.6f}"])
    return rows


# --- 2. the Fig 12 sweep ----------------------------------------------------------------------

def fig12_sweep_time():
    """Wall time of the 125-point Fig 12 sweep on 2 workers, the pool's start included."""
    scene = load("coupled", time__dt=STEP_DT)
    start = time.perf_counter()
    records = sweep(scene, FIG12_GRID, workers=2, progress=False)
    seconds = time.perf_counter() - start
    note(f"Fig 12 sweep: {len(records)} points in {seconds:.2f} s")
    return len(records), seconds


# --- 3. the same answer through solve_ivp -----------------------------------------------------

class SolveTimeout(Exception):
    """A solve_ivp run passed SOLVE_CAP_S."""


def dahl_rhs(scene, base_velocity, deadline: float):
    """d/dt (x, v, s) of the 1D Dahl model, written as a user would for solve_ivp.

    v_r = v - v_b(t);  ds/dt = v_r - |v_r| s k_t / F_c;  m dv/dt = k_d (v_d t - x) - k_t s.
    Raises SolveTimeout once ``deadline`` (perf_counter seconds) has passed.
    """
    m, k_d, v_d = scene.body.mass, scene.drive.k_d, scene.drive.v_d
    k_t, F_c = scene.contact.k_t, scene.F_c

    def rhs(t, state):
        if time.perf_counter() > deadline:
            raise SolveTimeout
        x, v, s = state
        v_r = v - base_velocity(t)
        return [v, (k_d * (v_d * t - x) - k_t * s) / m, v_r - abs(v_r) * s * k_t / F_c]

    return rhs


def averaging_window(scene) -> np.ndarray:
    """Midpoints of a uniform grid over the last ``averaged_cycles`` vibration cycles.

    The stepper averages F_d over the same whole cycles (eq 40); on a periodic
    signal the mean over a uniform grid converges spectrally to the cycle mean.
    """
    duration = scene.averaged_cycles / scene.vibration.f
    n = scene.averaged_cycles * POINTS_PER_CYCLE
    return scene.time.T - duration + (np.arange(n) + 0.5) * (duration / n)


def solve_ivp_ratio(scene, method: str, rtol: float):
    """(F_dv/F_d0, seconds) of the 1D Dahl ODE through solve_ivp; F_dv/F_d0 is None past the cap.

    The base velocity v_b = u0 w cos(w (t - t_on)) jumps from 0 at t_on, so
    the ODE is solved in its two smooth pieces, [0, t_on] and [t_on, T], as a
    careful user would, rather than making the step control find the jump.
    """
    t_on, T = scene.vibration.t_on, scene.time.T
    v_a, omega = scene.v_a, scene.omega
    atol = rtol * np.array([X_SCALE, V_SCALE, scene.F_c / scene.contact.k_t])
    start = time.perf_counter()
    deadline = start + SOLVE_CAP_S
    options = dict(method=method, rtol=rtol, atol=atol)
    try:
        at_rest = solve_ivp(dahl_rhs(scene, lambda t: 0.0, deadline),
                            (0.0, t_on), [0.0, 0.0, 0.0], **options)
        vibrated = solve_ivp(dahl_rhs(scene, lambda t: v_a * math.cos(omega * (t - t_on)), deadline),
                             (t_on, T), at_rest.y[:, -1], t_eval=averaging_window(scene), **options)
    except SolveTimeout:
        return None, time.perf_counter() - start
    seconds = time.perf_counter() - start
    if not (at_rest.success and vibrated.success):
        raise RuntimeError(f"solve_ivp {method} rtol={rtol:g}: {vibrated.message}")
    drive_force = scene.drive.k_d * (scene.drive.v_d * vibrated.t - vibrated.y[0])  # eq 17
    return float(np.mean(drive_force)) / scene.F_c, seconds  # Dahl: F_d0 = F_c


@dataclass
class Point:
    """One way of computing F_dv/F_d0 of the longitudinal case: its error and its time."""

    method: str
    setting: str
    ratio: float | None         # None: abandoned at SOLVE_CAP_S
    seconds: float
    error: float | None = None

    def row(self) -> list:
        if self.ratio is None:
            return [self.method, self.setting, "-", f"not done in {SOLVE_CAP_S:g} s",
                    f"> {SOLVE_CAP_S:g}"]
        return [self.method, self.setting, f"{self.ratio:.9f}", f"{self.error:.2e}",
                f"{self.seconds:.3f}"]


def reference(scene, plan: Plan):
    """The converged F_dv/F_d0 of the longitudinal case, and the rows that check it.

    Reference: the 1D stepper with the exact Dahl update at ``plan.reference_dt``.
    Checks: the same stepper at twice the step (its own convergence), the
    coupled stepper at the reference step, and solve_ivp at a tight tolerance.
    """
    dt = plan.reference_dt
    value = solve(scene.with_values({"time.dt": dt}), "longitudinal")[1]["F_dv_over_F_d0"]
    checks = [
        (f"1D stepper, exact, dt = {2 * dt:g}",
         solve(scene.with_values({"time.dt": 2 * dt}), "longitudinal")[1]["F_dv_over_F_d0"]),
        (f"coupled stepper, exact, dt = {dt:g}",
         solve(scene.with_values({"time.dt": dt}), "coupled")[1]["F_dv_over_F_d0"]),
    ]
    method, rtol = plan.tight
    tight, seconds = solve_ivp_ratio(scene, method, rtol)
    checks.append((f"solve_ivp {method}, rtol = {rtol:g} ({seconds:.1f} s)", tight))
    note(f"reference {value:.10f}; checks " + ", ".join(f"{v}" for _, v in checks))
    rows = [[f"**reference: 1D stepper, exact, dt = {dt:g}**", f"{value:.10f}", "0"]]
    rows += [[label, "-" if v is None else f"{v:.10f}", "-" if v is None else f"{v - value:+.1e}"]
             for label, v in checks]
    return value, rows


def stepper_points(scene, plan: Plan, ref: float) -> list:
    """Our steppers against the reference, both Dahl updates: error and time.

    The coupled stepper at each dt of CONVERGENCE_DTS; the 1D stepper, which
    integrates the very model handed to solve_ivp, at dt = 1e-6 only.
    """
    cases = [("coupled", dt) for dt in CONVERGENCE_DTS] + [("longitudinal", STEP_DT)]
    points = []
    for update in ("exact", "paper"):
        for stepper, dt in cases:
            seconds, ratio = timed_stepper(scene.with_values({"time.dt": dt, "contact.update": update}),
                                           stepper, plan.repeats)
            name = "coupled" if stepper == "coupled" else "1D"
            points.append(Point(f"{name} stepper, {update}", f"dt = {dt:g}", ratio, seconds,
                                abs(ratio - ref)))
    return points


def solve_ivp_points(scene, plan: Plan, ref: float, target: float) -> list:
    """solve_ivp at tolerances tightening until its error reaches ``target``.

    A method also stops tightening once one solve took LADDER_STOP_S: tighter
    settings only take longer, and the comparison needs the fastest one that
    reaches the target. Each solve runs once (they take seconds, not milliseconds).
    """
    points = []
    for method in plan.methods:
        for rtol in plan.rtols:
            ratio, seconds = solve_ivp_ratio(scene, method, rtol)
            error = None if ratio is None else abs(ratio - ref)
            points.append(Point(f"solve_ivp {method}", f"rtol = {rtol:g}", ratio, seconds, error))
            note(f"solve_ivp {method} rtol={rtol:g}: error {error}, {seconds:.1f} s")
            if error is None or error <= target or seconds > LADDER_STOP_S:
                break
    return points


def equal_error_rows(ours: list, theirs: list) -> list:
    """For each of our steppers at dt = 1e-6: the fastest solve_ivp setting at least as accurate."""
    rows = []
    done = [p for p in theirs if p.error is not None]
    for point in ours:
        matching = [p for p in done if p.error <= point.error]
        if matching:
            best = min(matching, key=lambda p: p.seconds)
            speedup = best.seconds / point.seconds
            rows.append([point.method, f"{point.error:.2e}", f"{point.seconds * 1e3:.1f} ms",
                         f"{best.method}, {best.setting}", f"{best.error:.2e}", f"{best.seconds:.1f} s",
                         f"**{speedup:.0f}x**", yes_no(speedup >= SPEEDUP_TARGET)])
        else:  # no setting got there in time: report the closest one honestly
            best = min(done, key=lambda p: p.error)
            rows.append([point.method, f"{point.error:.2e}", f"{point.seconds * 1e3:.1f} ms",
                         f"not reached; closest {best.method}, {best.setting}", f"{best.error:.2e}",
                         f"{best.seconds:.1f} s", f"> {best.seconds / point.seconds:.0f}x",
                         yes_no(best.seconds / point.seconds >= SPEEDUP_TARGET)])
    return rows


# --- report -----------------------------------------------------------------------------------

def yes_no(ok: bool) -> str:
    return "yes" if ok else "**no**"


def markdown_table(header: list, rows: list) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def cpu_name() -> str:
    """The processor's model name from /proc/cpuinfo (Linux), else its architecture."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.machine()


def machine_line(plan: Plan) -> str:
    return (f"{cpu_name()}, {os.cpu_count()} cores, "
            f"load {os.getloadavg()[0]:.2f} at start; Python {platform.python_version()}, "
            f"numpy {np.__version__}, numba {numba.__version__}, scipy {scipy.__version__}; "
            f"{'--quick' if plan is QUICK else 'full run'}, stepper times best of {plan.repeats}")


def plot_error_against_time(points: list, path: Path) -> None:
    """Log-log wall time against error in F_dv/F_d0, one line per method."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for method in dict.fromkeys(p.method for p in points):
        done = [p for p in points if p.method == method and p.error is not None]
        style = "o--" if method.startswith("solve_ivp") else "s-"
        ax.loglog([p.error for p in done], [p.seconds for p in done], style, ms=4, label=method)
    ax.set(xlabel=r"error in $F_{dv}/F_{d0}$ against the reference", ylabel="wall time (s)",
           title="longitudinal case, k_v = 6, T = 1 s")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats and solve_ivp settings")
    parser.add_argument("--out", type=Path, help="write analytic_speed.md and analytic_speed.png here")
    args = parser.parse_args(argv)
    plan = QUICK if args.quick else FULL
    started = time.perf_counter()
    header = machine_line(plan)

    steppers = stepper_speed(plan)
    points, sweep_seconds = fig12_sweep_time()

    scene = load("longitudinal", vibration__k_v=6.0, time__T=1.0, vibration__t_on=0.14)
    ref, reference_rows = reference(scene, plan)
    ours = stepper_points(scene, plan, ref)
    at_step = [p for p in ours if p.setting == f"dt = {STEP_DT:g}"]
    theirs = solve_ivp_points(scene, plan, ref, target=min(p.error for p in at_step))

    window = f"the last {scene.averaged_cycles} cycles"
    report = "\n\n".join([
        "# Analytic stepper speed",
        header,
        f"## 1. Stepper time, one 1 s scene at dt = {STEP_DT:g} (10^6 steps), numba warm\n\n"
        + markdown_table(["scene", "theta deg", "stepper", "update", "time ms",
                          f"<= {STEPPER_TARGET_S * 1e3:g} ms", "F_dv/F_d0"], steppers),
        "## 2. Fig 12 sweep, 5 k_v x 25 angles, 1 s each at dt = 1e-6, 2 workers\n\n"
        + markdown_table(["points", "wall time s (pool start included)", "per point s",
                          f"<= {SWEEP_TARGET_S:g} s"],
                         [[points, f"{sweep_seconds:.2f}", f"{sweep_seconds / points:.3f}",
                           yes_no(sweep_seconds <= SWEEP_TARGET_S)]]),
        f"## 3. Error against time: longitudinal, k_v = 6, T = 1 s, F_dv over {window}\n\n"
        "### Reference\n\n"
        + markdown_table(["F_dv/F_d0 of", "value", "minus reference"], reference_rows),
        "### Every setting (stepper: best of N; solve_ivp: one solve, 1D Dahl ODE in (x, v, s), "
        "atol = rtol x (1e-4 m, 1e-3 m/s, s_c))\n\n"
        + markdown_table(["method", "setting", "F_dv/F_d0", "error", "wall time s"],
                         [p.row() for p in ours + theirs]),
        f"### At equal error (our stepper at dt = {STEP_DT:g})\n\n"
        + markdown_table(["our stepper", "its error", "its time", "fastest solve_ivp as accurate",
                          "its error", "its time", "speed ratio", f">= {SPEEDUP_TARGET:g}x"],
                         equal_error_rows(at_step, theirs)),
        f"Total benchmark time {time.perf_counter() - started:.0f} s; "
        f"load {os.getloadavg()[0]:.2f} at the end.",
    ])
    print(report)
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "analytic_speed.md").write_text(report + "\n")
        plot_error_against_time(ours + theirs, args.out / "analytic_speed.png")


if __name__ == "__main__":
    main()
