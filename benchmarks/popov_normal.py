"""The lumped model under normal oscillation against the closed form of Popov et al.'s
stiff system: docs/validation.md's table "Normal oscillation: Popov et al.'s stiff system".

M. Popov, V. L. Popov, N. V. Popov, "Reduction of friction by normal oscillations. I.
Influence of contact stiffness", Friction 5 (2017) 45-55: a contact of tangential
stiffness k_x that slips at mu N, dragged at v_0 by a system far stiffer than it, its
normal force oscillating (the body without inertia normal to the contact). Their
macroscopic coefficient depends on a dimensionless sliding velocity and amplitude
alone; without contact loss it has the closed form
vibrofric.analytic.closed_form.normal_oscillation_ratio(v_tilde, alpha), with
alpha = the normal force's swing over F_N and v_tilde = k_x v_0 / (w mu alpha F_N).

The lumped model in that regime: the longitudinal scene without in-plane vibration,
the body driven at exactly v_d (drive.mode "velocity": the stiff system), the base
moving along Z at r = w / w_n = 20 (the body too heavy to follow it). Its normal
force then swings about F_N, sinusoidal while in contact, by
k_n A_n r^2 sqrt(1 + (2 zeta r)^2) / sqrt((1 - r^2)^2 + (2 zeta r)^2) (the contact's
dashpot, zeta = contact.zeta_n, the scene's default, adds 28% at r = 20): A_n is set so that this
is alpha F_N. Dahl's law with exponent 0 is the elastic-perfectly-plastic contact of
the closed form (k_t = k_x); the paper's exponent 1 approaches the limit gradually
and is shown beside it. 1000 steps a cycle; each answer the periodic orbit, with its
step-error estimate.

    PYTHONPATH=. python benchmarks/popov_normal.py        # ~1 min; prints the markdown table
"""

import math

import vibrofric as vf
from vibrofric.analytic.closed_form import normal_oscillation_ratio
from vibrofric.scene.schema import Contact

F_N, MU, K_T, F, MASS, R = 55.0, 0.1, 2e6, 4000.0, 0.5, 20.0
STEPS_PER_CYCLE = 1000
ALPHAS = (0.3, 0.6, 0.9)
V_TILDES = (0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.1)
EXPONENTS = (0.0, 1.0)


def force_swing_gain(r: float, zeta: float) -> float:
    """The normal force's swing over k_n A_n in contact at r = w / w_n (base-excited
    oscillator: N - F_N = k_n (z_b - z) + c_n (z_b' - z'))."""
    two_zeta_r = 2.0 * zeta * r
    return r * r * math.hypot(1.0, two_zeta_r) / math.hypot(1.0 - r * r, two_zeta_r)


def popov_scene(v_tilde: float, alpha: float, exponent: float):
    """The scene of Popov's groups (v_tilde, alpha) (module docstring)."""
    omega = 2.0 * math.pi * F
    k_n = MASS * (omega / R) ** 2
    amplitude = alpha * F_N / (k_n * force_swing_gain(R, Contact().zeta_n))
    v_d = v_tilde * omega * MU * alpha * F_N / K_T
    return vf.load_scene("longitudinal", drive__mode="velocity", drive__v_d=v_d,
                         contact__F_N=F_N, contact__mu=MU, contact__k_t=K_T,
                         contact__dahl_exponent=exponent, contact__k_n=k_n, body__mass=MASS,
                         vibration__k_v=0.0, vibration__f=F,
                         vibration__normal_amplitude=amplitude,
                         time__dt=1.0 / (STEPS_PER_CYCLE * F), time__method="periodic")


def main() -> None:
    print("| alpha | v~ | closed form | Dahl i = 0 | i = 0 - closed form | its step error "
          "| Dahl i = 1 | i = 1 - closed form |")
    print("|---|---|---|---|---|---|---|---|")
    for alpha in ALPHAS:
        for v_tilde in V_TILDES:
            closed = normal_oscillation_ratio(v_tilde, alpha)
            answers = []
            for exponent in EXPONENTS:
                summary = vf.run_analytic(popov_scene(v_tilde, alpha, exponent)).summary
                assert summary["periodic"]["method"] == "periodic", summary["periodic"]
                assert summary["contact_loss_fraction"] == 0.0
                answers.append((summary["F_dv_over_F_d0"], summary["error_estimate"]))
            (brittle, error), (paper, _) = answers
            print(f"| {alpha:g} | {v_tilde:g} | {closed:.4f} | {brittle:.4f} | "
                  f"{brittle - closed:+.1e} | {error:.0e} | {paper:.4f} | {paper - closed:+.3f} |")


if __name__ == "__main__":
    main()
