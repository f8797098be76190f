"""The vibrating base (eqs 23-25): its displacement along the vibration axis, step by step.

    u(t)  = u0 sin(w (t - t_on))   for t >= t_on, else 0      (eq 23)
    x_b   = u cos(theta),  y_b = u sin(theta)                 (eqs 24-25)
    z_b   = A_n sin(w (t - t_on) + phi)   for t >= t_on, else 0   (docs/model.md section 6)

The same compiled functions move the base in the analytic stepper and in
every FE integrator; the normal motion (normal_displacement) rides on the
in-plane motion's phase, so that the two stay in step to the bit.
"""

import math

from numba import njit

from ..friction_law.contract import FASTMATH


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


@njit(cache=True, error_model="numpy", fastmath=FASTMATH)
def normal_displacement(amplitude_n, omega, sin_n, cos_n, sin_phase, cos_phase):
    """(z_b, dz_b/dt): the base's normal motion z_b = A_n sin(w (t - t_on) + phi) and its
    velocity from the phase (sin, cos) of w (t - t_on) that base_displacement carries
    (sin_n, cos_n: of phi). Only for t >= t_on: the base rests before."""
    return (amplitude_n * (sin_phase * cos_n + cos_phase * sin_n),
            amplitude_n * omega * (cos_phase * cos_n - sin_phase * sin_n))


def normal_phase(phase_deg) -> tuple:
    """(sin phi, cos phi) of vibration.normal_phase_deg (None: 0)."""
    phi = math.radians(phase_deg or 0.0)
    return math.sin(phi), math.cos(phi)


def vibration_axis(theta_deg: float):
    """(cos theta, sin theta), exactly 0 or +-1 on the axes (eqs 24-25)."""
    theta = math.radians(theta_deg)
    return tuple(0.0 if abs(v) < 1e-15 else v for v in (math.cos(theta), math.sin(theta)))


def first_step_on(t_on: float, dt: float) -> int:
    """The first step i whose time i dt is at or past t_on (base_displacement's test, to
    the bit)."""
    i = max(0, math.ceil(t_on / dt))
    while i * dt < t_on:
        i += 1
    while i > 0 and (i - 1) * dt >= t_on:
        i -= 1
    return i
