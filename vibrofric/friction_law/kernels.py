"""Dahl and LuGre asperity updates, compiled with numba.

One contact node carries one lumped elastic asperity MN (paper Fig. 1): its
free end M sits on the base, its body end N' moves with the body. The state is
the deformation vector ``d = N' - M`` (2-vector in the contact plane), kept as
its length ``s = |d|`` and direction ``e = d / s`` (the paper's Table 1 carries
the same as s and the angle beta). The friction force the paper reports is ``F = k s e``
(eq 1, eqs 38-39) along ``e = d / s``; it acts on the body as ``-F``.

A time step has two phases (paper section 2, docs/model.md section 2):

phase 1 (eqs 18-22)
    the body end moves by the slip increment (body minus base) while M stays;
phase 2 (eqs 28-35)
    the free end moves with the base's transverse increment, scaled by eta_y.

In each phase the asperity is first stretched rigidly to the trial vector,
then its length relaxes by the Dahl (or LuGre) law along the trial direction.

``node_step`` is inlined into its callers' loops (numba ``inline="always"``;
10-15% faster, the time loops being latency-bound on its chain of square
roots, divisions and exponentials); all are compiled with ``arcp`` and ``contract`` only (reciprocals and fused
multiply-adds), so NaN and infinity still propagate and can be caught.
These functions take and return scalars so that a numba time loop (the lumped
stepper) and the per-node array loop (the FE model) inline the same code.
"""

import math

from numba import njit

FASTMATH = {"arcp", "contract"}

PAPER = 0  # explicit Euler update, as the paper (eqs 18, 31)
EXACT = 1  # exact solution for a constant v_r over the step

DAHL = 0
LUGRE = 1


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def relax_length(s, stretch, s_limit, update):
    """New asperity length after a trial change of length ``stretch = v_r dt``.

    Dahl (eqs 4-6): ds/dt = v_r [1 - (s / s_limit) sgn(v_r)], s_limit = F_c / k.

    paper (eq 18):  s' = s + v_r dt [1 - (s / s_limit) sgn(v_r)]
    exact:          s' = s_limit sgn + (s - s_limit sgn) exp(-|v_r| dt / s_limit)
    """
    if stretch == 0.0:
        return s
    sgn = 1.0 if stretch > 0.0 else -1.0
    if update == EXACT:
        return s_limit * sgn + (s - s_limit * sgn) * math.exp(-abs(stretch) / s_limit)
    return s + stretch * (1.0 - (s / s_limit) * sgn)


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def stribeck_limit(v_r, coulomb, stiction, v_s):
    """LuGre's sliding limit g(v_r) = F_c + (F_s - F_c) exp(-(v_r / v_s)^2) (eq 43)."""
    return coulomb + (stiction - coulomb) * math.exp(-((v_r / v_s) ** 2))


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def relax_phase(s, ex, ey, trial_x, trial_y, s_c, s_s, v_s, law, update, dt):
    """One phase: stretch the asperity rigidly to the trial vector, then relax.

    (s, ex, ey)  length and direction of the deformation before the phase
    trial        the deformation vector after the phase's rigid motion
    s_c, s_s     sliding and stiction lengths F_c / k, F_s / k (LuGre: g / k)

    v_r = (|trial| - s) / dt (eqs 19, 32); the new length follows the law
    (eqs 18, 31; LuGre eqs 44-45) along e = trial / |trial| (eqs 21-22,
    34-35); a zero-length trial keeps the previous direction (the paper's
    guards against 0/0). Returns (s_new, ex, ey, |trial|) with s_new >= 0: a
    length that relaxes through zero turns the direction round.
    """
    length = math.sqrt(trial_x * trial_x + trial_y * trial_y)
    if length > 0.0:
        inverse = 1.0 / length
        ex = trial_x * inverse
        ey = trial_y * inverse
    stretch = length - s
    s_limit = s_c
    if law == LUGRE:
        s_limit = stribeck_limit(stretch / dt, s_c, s_s, v_s)
    s_new = relax_length(s, stretch, s_limit, update)
    if s_new < 0.0:
        s_new, ex, ey = -s_new, -ex, -ey
    return s_new, ex, ey, length


@njit(cache=True, error_model="numpy", fastmath=FASTMATH, inline="always")
def node_step(
    s, ex, ey, slip_x, slip_y, free_x, free_y, normal_force,
    stiffness, mu, mu_s, v_s, h_t, h_v, law, update, dt,
):
    """Advance one node's asperity by one step; return (s, ex, ey, Fx, Fy).

    s, ex, ey        length and direction of the deformation d = N' - M
    slip_x, slip_y   phase-1 increment of the body end relative to the base
    free_x, free_y   phase-2 increment of the free end M (eta_y times the
                     base's transverse increment, eq 30)
    normal_force     the node's normal force (<= 0: out of contact)
    stiffness        the node's share of k_t
    mu, mu_s         Coulomb and stiction coefficients (F_c = mu F_N, eq 3;
                     F_s = mu_s F_N); Dahl ignores mu_s, v_s, h_t, h_v
    h_t, h_v         the node's shares of LuGre's contact and viscous damping

    Returns the new state and the friction force F (eq 1, 38-39; eqs 46-47
    for LuGre), which acts on the body as -F.
    """
    if normal_force <= 0.0 or mu <= 0.0 or stiffness <= 0.0:
        # Out of contact, frictionless or without contact area: no force, and
        # the asperity is released.
        return 0.0, ex, ey, 0.0, 0.0
    compliance = 1.0 / stiffness
    s_c = mu * normal_force * compliance
    s_s = mu_s * normal_force * compliance
    s0 = s

    # Phase 1 (eqs 18-22): the body end moves by the slip, the free end M stays.
    # A phase without motion leaves the asperity as it is.
    if slip_x != 0.0 or slip_y != 0.0:
        s, ex, ey, _ = relax_phase(s, ex, ey, s * ex + slip_x, s * ey + slip_y,
                                   s_c, s_s, v_s, law, update, dt)
    # Phase 2 (eqs 28-35): M moves by eta_y dy_b; d2 = s' e1 - (0, eta_y dy_b) (eq 33).
    trial_length = s
    if free_x != 0.0 or free_y != 0.0:
        s, ex, ey, trial_length = relax_phase(s, ex, ey, s * ex - free_x, s * ey - free_y,
                                              s_c, s_s, v_s, law, update, dt)

    force = stiffness * s  # eq 1
    if law == LUGRE:
        # eqs 46-47: contact damping on ds/dt and viscous damping on
        # v_r = (|N'_1 M'_2| - s) / dt, both over the whole step.
        force += h_t * (s - s0) / dt + h_v * (trial_length - s0) / dt
    return s, ex, ey, force * ex, force * ey
