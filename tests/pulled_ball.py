"""Cattaneo-Mindlin with the FE model: a hemisphere (tests/hemisphere.py, pole down) held
at the normal load P and pulled tangentially from its flat top, quasi-statically, on the
rigid base at rest (tests/test_curved_contacts.py, benchmarks/cattaneo_mindlin.py).

The scene: the ball's flat top is both its "load" (P as a uniform pressure) and its
"drive" (drive.mode = "velocity", drive.attach = "drive-group": the top's mean X
displacement x is prescribed, v_d t, and F_d = Q is the force that moves it); no gravity,
no vibration. The friction law is Dahl's with a tangential stiffness k_t so large that its
pre-sliding length mu P / k_t is far below the patch's elastic displacement: close to
rigid Coulomb, as Cattaneo and Mindlin assume.

Material and load are chosen so that the patch is resolvable: E = 5 GPa, nu = 0.3 (a
polymer's; Hertz and Mindlin are linear elastic, any E gives the same shapes), R = 10 mm,
P = 100 N: a = (3 P R / 4 E*)^(1/3) = 0.515 mm, a / R = 0.05.

The holder. The drive prescribes the top's mean X only, and a ball pulled above its
contact rolls on it (elastically free: nothing resists the moment Q R about the contact).
Cattaneo and Mindlin's ball is held by its holder, which translates without turning; here
the top's nodes are tied in Z to their weighted mean (held: springs k_hold w_a about the
preloaded state), so the top stays flat and the ball cannot turn about X or Y. The ties
stiffen the top against tilting by k_hold R^2 / 4 = 2.5e5 N m / rad: under the moment Q R
at Q = 45 N the contact moves by R theta = 0.02 um, 0.15% of delta.

What is compared (docs/validation.md, "Curved contacts"):

delta   The closed form's delta is the displacement of points far from the contact on a
        half-space. The top of a finite hemisphere also moves by the bulk's own shear
        under Q, a linear compliance C_bulk Q that the half-space lacks. A second run
        with mu large (the contact stuck throughout) is linear: x = C_stuck Q, C_stuck =
        C_bulk + C_0, C_0 = (2 - nu) / (8 G a) Mindlin's no-slip compliance (the closed
        form's slope at Q = 0). Compared (delta_errors): x(Q) - (C_stuck - C_0) Q, the
        top's displacement less the bulk's linear share, with delta(Q); and, using no
        slope of the closed form, the slip's own part x(Q) - C_stuck Q with
        delta(Q) - C_0 Q.
c       The stick radius at Q: the contact nodes closed and stuck (|f_i| < 0.98 mu N_i, the
        frames' contact_state) against those slipping; c is the mean of the largest
        stuck radius and the smallest slipping radius beyond it (half a node spacing of
        resolution: the mesh's, not the method's).
"""

import dataclasses
import math
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from hemisphere import hemisphere

from vibrofric import scene as scenes
from vibrofric.analytic import contact_mechanics as cm
from vibrofric.fem import simulate
from vibrofric.fem.model import fe_model
from vibrofric.fem.outputs.contact_patch import SLIP, STICK

RADIUS, LOAD, E, NU, MU = 0.01, 100.0, 5e9, 0.3, 0.5
STUCK_MU = 10.0     # the stuck run's: Q stays below 0.07 mu P (Mindlin's slipping annulus
                    # 0.02 a wide, inside the outer ring of nodes)
K_HOLD = 1e10       # N/m, the holder's ties in all: their highest frequency ~0.6 MHz, far
                    # below the mesh's own (14 MHz), so the explicit step is the mesh's
K_T = 1e9           # N/m for the whole patch: mu P / k_t = 0.05 um, 0.3% of delta at mu P
V_D = 5e-3          # m/s: mu P is reached after ~15 um, 3 ms, 240 wave transits of
                    # the ball (R / sqrt(E / rho) = 12.5 us): quasi-static
PULL_TIME = 3e-3    # s: Q reaches 0.94 mu P
FINE_RADIUS = 1.2e-3  # m: the pole's mesh size holds within 2.3 a of the pole
SCENE = Path(__file__).resolve().parent.parent / "scenes" / "longitudinal.toml"


def hertz_radius() -> float:
    return cm.hertz_radius(LOAD, RADIUS, E, NU)


def ball(directory, pole_size):
    """The hemisphere of pole mesh ``pole_size`` (m) with its top as the drive group."""
    return hemisphere(directory, RADIUS, pole_size, FINE_RADIUS, drive=True)


def stable_step(pole_size) -> float:
    """The explicit step taken on the pole mesh ``pole_size``, s: 0.7 of the stable step
    fe_model reports (2.1e-8 s at 150 um, 1.5e-8 s at 100 um), which scales with the size."""
    return 1.4e-8 * pole_size / 1e-4


def pull_scene(mu, T, dt, **values):
    """The longitudinal scene turned into the pull: no vibration, stepped, no estimates,
    400 rows of series."""
    return scenes.load(SCENE).with_values({
        "contact.F_N": LOAD, "contact.mu": mu, "contact.k_t": K_T,
        "body.gravity": 0.0, "body.density": 7850.0, "body.E": E, "body.nu": NU,
        "drive.mode": "velocity", "drive.attach": "drive-group", "drive.v_d": V_D,
        "vibration.k_v": 0.0, "time.T": T, "time.dt": dt, "time.method": "transient",
        "time.series_dt": dt * max(1, round(T / dt / 400)), "time.error_estimate": False,
        "fem.output_every": 0, **values})


def held(model, k_hold=K_HOLD):
    """``model`` with its drive group's nodes tied in Z to their weighted mean: the energy
    k_hold / 2 sum_a w_a (dz_a - sum_b w_b dz_b)^2 of dz = u_z - u0_z, whose stiffness is
    k_hold (W - w w^T) on those Z DOFs; K_tie u0 joins the load so that the preload stays
    the static state."""
    dofs = 3 * model.attach_nodes + 2
    w = model.attach_weights
    tie = k_hold * (np.diag(w) - np.outer(w, w))
    rows, cols = np.meshgrid(dofs, dofs, indexing="ij")
    k_tie = sp.csr_matrix((tie.ravel(), (rows.ravel(), cols.ravel())),
                          shape=model.stiffness.shape)
    disc = dataclasses.replace(model.disc, stiffness=(model.stiffness + k_tie).tocsr())
    return dataclasses.replace(model, disc=disc, load=model.load + k_tie @ model.u0)


def run(body, scene):
    """simulate.run_fe of ``scene`` with ``body`` (a BodyMesh) as its body, held (held)."""
    saved = fe_model.body_of, fe_model.block_size, simulate.build_model
    fe_model.body_of = lambda scene, level=None: body
    fe_model.block_size = lambda scene: None
    simulate.build_model = lambda scene, comm: held(saved[2](scene, comm))
    try:
        return simulate.run_fe(scene)
    finally:
        fe_model.body_of, fe_model.block_size, simulate.build_model = saved


def ringing_period(stuck) -> float:
    """The period of the held ball's vibration that rings through the pull, s: the
    strongest line of the stuck run's x against its straight line in F_d (measured:
    15.2 kHz, +-0.3 um of x, undamped to the end: the damping acts at the mesh's top
    mode). The cycled ball rings alike at 1e-9 m/s, so its source is not the drive's
    start; it is not pinned down."""
    s = stuck.series
    F, x = s.F_d, s.x
    late = x > x.max() / 3
    residual = x - np.polyval(np.polyfit(F[late], x[late], 1), F)
    residual = residual[late] - residual[late].mean()
    row = s.t[1] - s.t[0]
    spectrum = np.abs(np.fft.rfft(residual))
    return 1.0 / np.fft.rfftfreq(residual.size, row)[1 + int(spectrum[1:].argmax())]


def quasi_static(result, period):
    """(F_d, x) of a pull averaged over one ``period`` of its ringing (a running mean over
    the rows within it, the rows a whole window holds): the quasi-static curve beneath."""
    s = result.series
    rows = max(1, int(round(period / (s.t[1] - s.t[0]))))
    window = np.ones(rows) / rows
    return np.convolve(s.F_d, window, "valid"), np.convolve(s.x, window, "valid")


def displacement_at(curve, Q):
    """The X displacement x where the curve (F_d, x) first reaches Q, interpolated."""
    F, x = curve
    i = int(np.argmax(F >= Q))
    if F[i] < Q:
        raise ValueError(f"the pull never reached Q = {Q:g} N (at most {F.max():g} N)")
    return float(np.interp(Q, F[i - 1:i + 1], x[i - 1:i + 1]))


def time_at(result, Q):
    """The time the pull's F_d first reaches Q, interpolated, s."""
    F, t = result.series.F_d, result.series.t
    i = int(np.argmax(F >= Q))
    return float(np.interp(Q, F[i - 1:i + 1], t[i - 1:i + 1]))


def stuck_compliance(stuck) -> float:
    """C_stuck = dx / dQ of the stuck run, m/N: the slope fitted (least squares) to its
    quasi-static curve past a third of its pull."""
    F, x = quasi_static(stuck, ringing_period(stuck))
    late = x > x.max() / 3
    return float(np.polyfit(F[late], x[late], 1)[0])


def no_slip_compliance() -> float:
    """Mindlin's C_0 = (2 - nu) / (8 G a) = 1 / (8 G* a): the closed form's slope at Q = 0."""
    return 1.0 / (8.0 * cm.tangential_modulus(E, NU) * hertz_radius())


def delta_errors(pulled, stuck, fractions):
    """{q: (total, nonlinear)} relative errors of the FE against Cattaneo-Mindlin at
    Q = q mu P, on the quasi-static curves (the stuck run's ringing period averaged out):
      total      x(Q) - (C_stuck - C_0) Q, the top's displacement less the bulk's linear
                 share, against delta(Q);
      nonlinear  x(Q) - C_stuck Q, the slip's own displacement, against delta(Q) - C_0 Q
                 (no closed-form slope used: the stricter, a difference of near numbers).
    """
    C, C0 = stuck_compliance(stuck), no_slip_compliance()
    curve = quasi_static(pulled, ringing_period(stuck))
    errors = {}
    for q in fractions:
        Q = q * MU * LOAD
        x = displacement_at(curve, Q)
        delta = cm.mindlin_displacement(Q, MU, LOAD, hertz_radius(), E, NU)
        errors[q] = ((x - (C - C0) * Q) / delta - 1.0, (x - C * Q) / (delta - C0 * Q) - 1.0)
    return errors


def stick_radius(result) -> float:
    """The stick radius at the run's last step, m: the mean of the largest radius of a
    stuck node (contact_state STICK) and the smallest radius of a slipping node beyond it,
    radii from the pole (x = y = 0, where the held ball's patch stays centred)."""
    fields = result.fields
    nodes = fields["contact_nodes"]
    state = fields["contact_state"][nodes]
    r = np.hypot(*fields["coordinates"][nodes, :2].T)
    stuck = r[state == STICK].max()
    beyond = r[(state == SLIP) & (r > stuck)]
    return 0.5 * (stuck + beyond.min()) if beyond.size else stuck


# Mindlin-Deresiewicz: the held ball at rest (the drive at 1e-9 m/s: 1e-11 m over the
# run) on the base moving in X as u0 sin(w t), slow against the ball (a shear wave crosses
# it in R / sqrt(G / rho) = 20 us, a 250th of a 200 Hz cycle), so that Q cycles
# quasi-statically between -Q* and +Q*. The base's displacement amplitude u0 = k_v v_d / w.
CYCLE_FREQUENCY = 200.0   # Hz
HELD_SPEED = 1e-9         # m/s
# u0 for a target q = Q* / mu P: the closed form's delta(Q*) with the bulk's ~10% added
# (C_stuck / C_0, benchmarks/cattaneo_mindlin.py) less a margin, so Q* stays below mu P
AMPLITUDE_FACTOR = 1.05


def cycle_scene(q, dt):
    """The ball held and the base cycled for a Q* near q mu P: 2.25 cycles (the first
    quarter loads from 0, the loop from t = 1 / f on is Masing's steady one)."""
    f = CYCLE_FREQUENCY
    Q = q * MU * LOAD
    u0 = AMPLITUDE_FACTOR * cm.mindlin_displacement(Q, MU, LOAD, hertz_radius(), E, NU)
    return pull_scene(MU, 2.25 / f, dt, **{
        "drive.v_d": HELD_SPEED, "vibration.f": f, "vibration.t_on": 0.0,
        "vibration.k_v": 2.0 * math.pi * f * u0 / HELD_SPEED, "time.average_cycles": 1})


def cycle_dissipation(result):
    """(Q*, W): over the cycle 1 / f <= t <= 2 / f, the tangential load's amplitude (half
    its peak-to-peak, N) and the loop's area W = |oint Q d(x - x_b)| (trapezoids over
    every step's row, J): the work the holder's force Q does on the ball's displacement
    relative to the base, which only the slip dissipates (the bulk is elastic; the
    damping's share at 200 Hz is ~1e-6 of the top mode's 6%). Q and x - x_b are averaged
    over one period of the ball's ringing (as the pull's, quasi_static: +-1.3 N on Q*
    ~ 30 N otherwise), the strongest line of Q above ten times the cycle's frequency."""
    s = result.series
    row = s.t[1] - s.t[0]
    spectrum = np.abs(np.fft.rfft(s.F_d - s.F_d.mean()))
    frequency = np.fft.rfftfreq(s.F_d.size, row)
    fast = frequency > 10.0 * CYCLE_FREQUENCY
    rows = max(1, int(round(1.0 / frequency[fast][spectrum[fast].argmax()] / row)))
    window = np.ones(rows) / rows
    t, Q, relative = (np.convolve(y, window, "valid") for y in (s.t, s.F_d, s.x - s.x_b))
    cycle = (t >= 1.0 / CYCLE_FREQUENCY) & (t <= 2.0 / CYCLE_FREQUENCY)
    Q, relative = Q[cycle], relative[cycle]
    return 0.5 * (Q.max() - Q.min()), abs(float(np.trapz(Q, relative)))
