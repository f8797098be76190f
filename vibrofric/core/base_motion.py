"""The vibrating base (eqs 23-25): its displacement along the vibration axis, step by step.

    u(t)  = u0 sin(w (t - t_on))   for t >= t_on, else 0      (eq 23)
    x_b   = u cos(theta),  y_b = u sin(theta)                 (eqs 24-25)

The same compiled functions move the base in the analytic stepper and in
every FE integrator.
"""

import math

from numba import njit


@njit(cache=True, error_model="numpy")
def base_phase(i, dt, omega, t_on, sin_phase, cos_phase, cos_step, sin_step):
    """(sin, cos) of w (t_i - t_on), the phase of u(t) = u0 sin(w (t - t_on)) (eq 23).

    Advanced from the previous step by a rotation through w dt (two
    multiply-adds instead of a sine); re-anchored on the exact sine every
    1024 steps, which keeps the rounding drift below 1e-13.
    """
    steps_on = i - int(math.ceil(t_on / dt - 1e-9))
    if steps_on & 1023 == 0:
        phase = omega * (i * dt - t_on)
        return math.sin(phase), math.cos(phase)
    return (sin_phase * cos_step + cos_phase * sin_step,
            cos_phase * cos_step - sin_phase * sin_step)


@njit(cache=True, error_model="numpy")
def base_displacement(i, dt, omega, t_on, amplitude, sin_phase, cos_phase, cos_step, sin_step):
    """(u, sin, cos): the base's displacement along its axis at t_i = i dt,
    u = amplitude sin(w (t_i - t_on)) from t_on, 0 before (eq 23), and the
    phase carried to the next step (base_phase)."""
    if i * dt < t_on:
        return 0.0, sin_phase, cos_phase
    sin_phase, cos_phase = base_phase(i, dt, omega, t_on, sin_phase, cos_phase, cos_step, sin_step)
    return amplitude * sin_phase, sin_phase, cos_phase


def vibration_axis(theta_deg: float):
    """(cos theta, sin theta), exactly 0 or +-1 on the axes (eqs 24-25)."""
    theta = math.radians(theta_deg)
    return tuple(0.0 if abs(v) < 1e-15 else v for v in (math.cos(theta), math.sin(theta)))
