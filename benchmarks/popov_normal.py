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

Past contact loss (alpha > 1, the indentation's swing over its mean: the body "jumps"),
the second table: the same closed form (the spring released while out of contact,
sticking again from the landing) against the lumped body at r = 50 with the contact's
dashpot nearly off (zeta_n = 2e-5), so that N is the spring's k_n times the imposed
indentation, clipped at 0 (the dashpot leads it by 2 zeta_n r = 0.002 rad); the body
sinks until the contact carries F_N on average, which sets the indentation's mean d_0
(k_n d_0 mean_contact_load(alpha) = F_N). Dahl's law at exponent 0, 2000 steps a cycle.

    PYTHONPATH=. python benchmarks/popov_normal.py        # prints both markdown tables
"""

import math

import vibrofric as vf
from vibrofric.analytic.closed_form import mean_contact_load, normal_oscillation_ratio
from vibrofric.scene.schema import Contact

F_N, MU, K_T, F, MASS, R = 55.0, 0.1, 2e6, 4000.0, 0.5, 20.0
STEPS_PER_CYCLE = 1000
ALPHAS = (0.3, 0.6, 0.9)
V_TILDES = (0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.1)
EXPONENTS = (0.0, 1.0)
# past contact loss
JUMP_R, JUMP_ZETA, JUMP_STEPS_PER_CYCLE = 50.0, 2e-5, 2000
JUMP_ALPHAS = (1.2, 1.5, 2.0, 3.0)
JUMP_V_TILDES = (0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 1.1)


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


def jumping_scene(v_tilde: float, alpha: float):
    """The scene of Popov's groups past contact loss (module docstring): the indentation
    swings by alpha d_0 about its mean d_0."""
    omega = 2.0 * math.pi * F
    k_n = MASS * (omega / JUMP_R) ** 2
    k_n_d_0 = F_N / mean_contact_load(alpha)
    amplitude = alpha * k_n_d_0 / (k_n * force_swing_gain(JUMP_R, JUMP_ZETA))
    v_d = v_tilde * omega * MU * alpha * k_n_d_0 / K_T
    return vf.load_scene("longitudinal", drive__mode="velocity", drive__v_d=v_d,
                         contact__F_N=F_N, contact__mu=MU, contact__k_t=K_T,
                         contact__dahl_exponent=0.0, contact__k_n=k_n,
                         contact__zeta_n=JUMP_ZETA, body__mass=MASS,
                         vibration__k_v=0.0, vibration__f=F,
                         vibration__normal_amplitude=amplitude,
                         time__dt=1.0 / (JUMP_STEPS_PER_CYCLE * F), time__method="periodic")


def contact_loss_table() -> None:
    print("| alpha | v~ | closed form | Dahl i = 0 | i = 0 - closed form | its step error "
          "| out of contact | closed form's arc |")
    print("|---|---|---|---|---|---|---|---|")
    for alpha in JUMP_ALPHAS:
        arc = 1.0 - math.acos(-1.0 / alpha) / math.pi
        for v_tilde in JUMP_V_TILDES:
            closed = normal_oscillation_ratio(v_tilde, alpha)
            summary = vf.run_analytic(jumping_scene(v_tilde, alpha)).summary
            assert summary["periodic"]["method"] == "periodic", summary["periodic"]
            answer = summary["F_dv_over_F_d0"]
            print(f"| {alpha:g} | {v_tilde:g} | {closed:.4f} | {answer:.4f} | "
                  f"{answer - closed:+.1e} | {summary['error_estimate']:.0e} | "
                  f"{summary['contact_loss_fraction']:.4f} | {arc:.4f} |")


def main() -> None:
    in_contact_table()
    print()
    contact_loss_table()


def in_contact_table() -> None:
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
