"""The coarse ball's steady answer against the step, and the scheme's frequency of the
ball's rocking on its pole: why its answers between 5e-6 and 2e-6 s are not in the
step's asymptotic range (docs/fe-model.md, "The step on a curved body").

    PYTHONPATH=. python benchmarks/ball_step_scan.py [--out DIR]

Two Markdown tables on stdout (and DIR/ball_step_scan.md):

modes  the ball's natural frequencies up to 8 f (f the vibration's) on its preload's
       patch held by the linearized contact (k_t w_i in X, Y, k_pen w_i in Z:
       "stuck"; without k_t: "slipping"), in the full model (903 DOFs, dense) and in
       the reduced model at fem.interface_reach 3 and "all".
scan   F_dv/F_d0 (the steady cycle, reduced, fem.interface_reach 3 and "all", and
       3 at fem.rho_infinity 0.5) at whole numbers N of steps a cycle (dt = 1/(N f)),
       each beside numerical_frequency of its reduced model's first stuck mode above
       5 f at that step: the scheme's own frequency of that mode, over f.

Generalized-alpha lengthens a mode's period by a fraction that grows as (w dt)^2 and
more where rho_inf is smaller (Chung & Hulbert, J. Appl. Mech. 60 (1993) 371); where
the mode lies a few per cent from a harmonic of the friction force, the step moves it
across that harmonic's resonance, and the answer follows the scheme's frequency,
whatever rho_inf. Each answer is the steady cycle shot from steady sliding (no Floquet
check; a run that finds none says "none"), a few seconds each once compiled.
"""

import argparse
import math
from pathlib import Path

import numpy as np
import scipy.linalg as la

import vibrofric as vf
from vibrofric.fem.integrators.reduction import ReducedRun
from vibrofric.fem.model.fe_model import build_model
from vibrofric.fem.simulate import _answer_at

ROOT = Path(__file__).resolve().parent.parent
STEPS_PER_CYCLE = range(50, 131, 8)
MAX_HARMONIC = 8
RUNS = [("reach 3", {"fem.interface_reach": 3.0}),
        ('"all"', {"fem.interface_reach": "all"}),
        ("reach 3, rho_inf 0.5", {"fem.interface_reach": 3.0, "fem.rho_infinity": 0.5})]


def numerical_frequency(omega: float, dt: float, rho_inf: float) -> float:
    """The frequency (rad/s) at which generalized-alpha (generalized_alpha.coefficients)
    carries an undamped mode of frequency omega at the step dt: the angle a step of the
    principal root of its amplification matrix, over dt (the root pair with the largest
    modulus; rho_inf = 1, the trapezoidal rule: 2 arctan(omega dt / 2) / dt)."""
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma, beta = 0.5 - am + af, 0.25 * (1.0 - am + af) ** 2
    w2 = omega * omega
    # (q, v, a)_{n+1} from (q, v, a)_n: the Newmark updates and the equation at n+1-alpha
    left = np.array([[1.0, 0.0, -dt * dt * beta], [0.0, 1.0, -dt * gamma],
                     [(1.0 - af) * w2, 0.0, 1.0 - am]])
    right = np.array([[1.0, dt, dt * dt * (0.5 - beta)], [0.0, 1.0, dt * (1.0 - gamma)],
                      [-af * w2, 0.0, -am]])
    roots = np.linalg.eigvals(np.linalg.solve(left, right))
    principal = roots[np.argmax(np.abs(roots))]
    return abs(np.angle(principal)) / dt


def patch_frequencies(K, M, dofs, held_x, held_z) -> dict:
    """Hz: {"stuck", "slipping"}: the natural frequencies of (K + L, M) up to MAX_HARMONIC
    f with L = held_x on the patch's X and Y DOFs (none: slipping) and held_z on Z."""
    out = {}
    for label, tangential in (("stuck", held_x), ("slipping", 0.0 * held_x)):
        KL = np.array(K, dtype=float)
        x, y, z = dofs[:, 0], dofs[:, 1], dofs[:, 2]
        KL[x, x] += tangential
        KL[y, y] += tangential
        KL[z, z] += held_z
        w2 = la.eigh(KL, M, eigvals_only=True)
        out[label] = np.sqrt(np.abs(w2)) / (2.0 * math.pi)
    return out


def first_above(frequencies: np.ndarray, f: float) -> float:
    """The first of ``frequencies`` above 5 f (the rocking modes near the 7th harmonic)."""
    return float(frequencies[frequencies > 5.0 * f][0])


def modes_table(scene) -> tuple[list[str], dict]:
    """The modes table's rows, and {run label: its reduced model's first stuck mode above
    5 f, Hz}."""
    f = scene.vibration.f
    model = build_model(scene, None)
    patch = np.flatnonzero(np.asarray(model.in_contact0, dtype=bool))
    nodes = model.contact_nodes[patch]
    dofs = 3 * nodes[:, None] + np.arange(3)[None, :]
    mass = np.asarray(model.disc.mass)
    full = patch_frequencies(model.stiffness.toarray(), np.diag(mass) if mass.ndim == 1 else mass,
                             dofs, scene.contact.k_t * model.area_share[patch],
                             model.penalty_share[patch])
    rows = ["| model | patch | modes up to 8 f, kHz (over f) |", "|---|---|---|"]

    def row(label, frequencies):
        for kind, hz in frequencies.items():
            hz = hz[(hz > 1.0) & (hz <= MAX_HARMONIC * f)]
            text = ", ".join(f"{h / 1e3:.2f} ({h / f:.3f})" for h in hz)
            rows.append(f"| {label} | {kind} | {text} |")

    row("full", full)
    modes = {}
    for label, overrides in RUNS:
        run = ReducedRun(scene.with_values(overrides), model)
        on = np.flatnonzero(run.assumed > 0.0)
        reduced = patch_frequencies(
            run.system.stiffness, run.system.mass, run.system.contact_dofs[on],
            scene.contact.k_t * run.model.area_share[on], run.model.penalty_share[on])
        modes[label] = first_above(reduced["stuck"], f)
        if "rho_inf" not in label:      # the reduction does not depend on the scheme
            row(f"reduced, {label}", reduced)
    return rows, modes


def scan_table(scene, modes: dict) -> list[str]:
    f = scene.vibration.f
    model = build_model(scene, None)
    rows = ["| N | dt s | " + " | ".join(f"F_dv/F_d0, {label} | scheme's mode / f"
                                         for label, _ in RUNS) + " |",
            "|---|---|" + "---|---|" * len(RUNS)]
    for steps in STEPS_PER_CYCLE:
        dt = 1.0 / (steps * f)
        cells = [str(steps), f"{dt:.4g}"]
        for label, overrides in RUNS:
            at = scene.with_values(overrides)
            answer = _answer_at(at, model, dt, None, True)
            mode = numerical_frequency(2 * math.pi * modes[label], dt, at.fem.rho_infinity)
            cells += ["none" if answer.ratio is None else f"{answer.ratio:.5f}",
                      f"{mode / (2 * math.pi * f):.3f}"]
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    scene = vf.load_scene(ROOT / "scenes" / "ball.toml",
                          **{"fem.integrator": "reduced", "fem.output_every": 0})
    rows, modes = modes_table(scene)
    text = "\n".join(rows + [""] + scan_table(scene, modes)) + "\n"
    print(text, end="")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "ball_step_scan.md").write_text(text)


if __name__ == "__main__":
    main()
