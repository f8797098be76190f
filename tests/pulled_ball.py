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
the project's (drive.holder = "translating", vibrofric/fem/model/holder.py): the top's
nodes tied in X, Y and Z to their weighted mean, so the top moves as one rigid
translation, carrying P and the pull, and the ball cannot turn about X or Y.

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
c       The stick radius at Q, read two ways from the contact nodes closed and stuck
        (|f_i| < 0.98 mu N_i, the frames' contact_state) or slipping: stick_radius, the
        mean of the largest stuck radius and the smallest slipping radius beyond it (half
        a node spacing of resolution: the mesh's, not the method's); stick_radius_fit,
        where the stuck nodes' tractions, on Mindlin's shape, put the front (between
        the nodes).
"""

import math
from pathlib import Path

import numpy as np

from hemisphere import INNER, Ring, hemisphere

from vibrofric import scene as scenes
from vibrofric.analytic import contact_mechanics as cm
from vibrofric.fem import simulate
from vibrofric.fem.model import fe_model
from vibrofric.fem.outputs.contact_patch import SLIP, STICK

RADIUS, LOAD, E, NU, MU = 0.01, 100.0, 5e9, 0.3, 0.5
STUCK_MU = 10.0     # the stuck run's: Q stays below 0.07 mu P (Mindlin's slipping annulus
                    # 0.02 a wide, inside the outer ring of nodes)
K_T = 1e9           # N/m for the whole patch: mu P / k_t = 0.05 um, 0.3% of delta at mu P
V_D = 5e-3          # m/s: mu P is reached after ~15 um, 3 ms, 240 wave transits of
                    # the ball (R / sqrt(E / rho) = 12.5 us): quasi-static
PULL_TIME = 3e-3    # s: Q reaches 0.94 mu P
FINE_RADIUS = 1.2e-3  # m: the pole's mesh size holds within 2.3 a of the pole
SCENE = Path(__file__).resolve().parent.parent / "scenes" / "longitudinal.toml"


def hertz_radius() -> float:
    return cm.hertz_radius(LOAD, RADIUS, E, NU)


# A ring's band: within 0.12 a of the circle r = a, Mindlin's slipping annulus at
# Q* = 0.3 mu P (a - c = 0.112 a, Johnson eq 7.40) and the patch's edge
RING_HALF_WIDTH = 0.12


def ball(directory, pole_size, ring_size=None, annulus_q=None):
    """The hemisphere of pole mesh ``pole_size`` (m) with its top as the drive group; with
    ``ring_size`` (m) refined further to that edge within RING_HALF_WIDTH a of the patch's
    edge r = a (hemisphere.Ring); with ``annulus_q`` too, within RING_HALF_WIDTH a of the
    band from Mindlin's stick radius at Q* = annulus_q mu P, c = a (1 - q)^(1/3) (Johnson
    eq 7.40), to a: the whole slipping annulus of that cycle (0.26 a wide at q = 0.6,
    0.54 a at 0.9) with the same margin on either side."""
    a = hertz_radius()
    inner = (None if annulus_q is None
             else cm.stick_radius(annulus_q * MU * LOAD, MU, LOAD, a))
    ring = None if ring_size is None else Ring(a, ring_size, RING_HALF_WIDTH * a, inner)
    return hemisphere(directory, RADIUS, pole_size, FINE_RADIUS, drive=True, ring=ring)


def stable_step(pole_size, ring_size=None) -> float:
    """The explicit step taken on the pole mesh ``pole_size`` (and ``ring_size``), s: 0.7 of
    the stable step fe_model reports (2.1e-8 s at 150 um, 1.5e-8 s at 100 um), which scales
    with the smallest element."""
    return 1.4e-8 * min(pole_size, ring_size or pole_size) / 1e-4


def pull_scene(mu, T, dt, **values):
    """The longitudinal scene turned into the pull, the top held (drive.holder): no
    vibration, stepped, no estimates, 400 rows of series."""
    return scenes.load(SCENE).with_values({
        "contact.F_N": LOAD, "contact.mu": mu, "contact.k_t": K_T,
        "body.gravity": 0.0, "body.density": 7850.0, "body.E": E, "body.nu": NU,
        "drive.mode": "velocity", "drive.attach": "drive-group", "drive.holder": "translating",
        "drive.v_d": V_D,
        "vibration.k_v": 0.0, "time.T": T, "time.dt": dt, "time.method": "transient",
        "time.series_dt": dt * max(1, round(T / dt / 400)), "time.error_estimate": False,
        "fem.output_every": 0, **values})


def run(body, scene):
    """simulate.run_fe of ``scene`` with ``body`` (a BodyMesh) as its body."""
    saved = fe_model.body_of, fe_model.block_size
    fe_model.body_of = lambda scene, level=None: body
    fe_model.block_size = lambda scene: None
    try:
        return simulate.run_fe(scene)
    finally:
        fe_model.body_of, fe_model.block_size = saved


def ringing_period(stuck) -> float:
    """The period of the held ball's vibration that rings through the pull, s: the
    strongest line of the stuck run's x against its straight line in F_d (measured:
    15.2 kHz, +-0.3 um of x, undamped to the end: the damping acts at the mesh's top
    mode). It is started by the motion's start, the drive's step from rest to v_d (the
    cycled run's: the base's, from rest to w u0): held at rest, the ball's F_d stays
    within 5e-6 N."""
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


def stick_radius_fit(result, mu=MU):
    """(c, slope): the stick radius of the Cattaneo-Mindlin traction field closest to the
    run's last step, m, read between the nodes (stick_radius reads the front to half a
    node spacing), and the fitted line's slope.

    Mindlin's traction inside the stick circle (Johnson eqs 7.38-7.39) is
    q(r) = mu p0 / a [sqrt(a^2 - r^2) - sqrt(c^2 - r^2)] on the Hertz pressure
    p(r) = p0 sqrt(a^2 - r^2) / a, so a stuck node's ratio phi = |q| / mu p obeys

        y = (1 - phi)^2 (a^2 - r^2) = c^2 - r^2,

    a straight line in r^2 of slope -1 that reaches 0 at r = c. The line is fitted (least
    squares, slope free) to the stuck nodes (contact_state STICK) inside a, with phi from
    each node's friction traction and pressure and a from the same step's pressures (the
    Hertz fit of tests/hemisphere.py: p^2 linear in r^2 over the nodes above INNER of the
    largest); c where it reaches 0. Its slope says how near the FE's field is Mindlin's
    shape (-1)."""
    fields = result.fields
    nodes = fields["contact_nodes"]
    r2 = (fields["coordinates"][nodes, :2] ** 2).sum(axis=1)
    pressure = fields["contact_pressure"][nodes]
    traction = np.hypot(*fields["friction_traction"][nodes, :2].T)
    inner = pressure > INNER * pressure.max()
    slope, intercept = np.polyfit(r2[inner], pressure[inner] ** 2, 1)
    a2 = -intercept / slope
    stuck = (fields["contact_state"][nodes] == STICK) & (r2 < a2)
    phi = traction[stuck] / (mu * pressure[stuck])
    y = (1.0 - phi) ** 2 * (a2 - r2[stuck])
    slope, intercept = np.polyfit(r2[stuck], y, 1)
    return math.sqrt(-intercept / slope), float(slope)


# Mindlin-Deresiewicz: the held ball at rest (the drive at 1e-9 m/s: 1e-11 m over the
# run) on the base moving in X as u0 sin(w t), slow against the ball (a shear wave crosses
# it in R / sqrt(G / rho) = 20 us, a 100th of a 500 Hz cycle; the ball rings at 15 kHz), so
# that Q cycles quasi-statically between -Q* and +Q*. The base's displacement amplitude
# u0 = k_v v_d / w. Measured on the 150 um mesh at Q* ~ 0.585 mu P: 500 Hz and 200 Hz (2.25
# cycles each) read the same loop to 0.5%, 500 Hz in 2.5 times less time.
CYCLE_FREQUENCY = 500.0   # Hz
CYCLES = 2.25             # the first quarter loads from 0; the loop is read over the last
                          # cycle (cycle_dissipation). One cycle after the first quarter
                          # (1.25) read 59.4 uJ against the 2.25 cycles' 53.1 at 500 Hz on
                          # the 150 um mesh (its top then tied in Z only): the first loop
                          # is not yet the steady one
HELD_SPEED = 1e-9         # m/s
# u0 for a target q = Q* / mu P: the closed form's delta(Q*) with the bulk's ~10% added
# (C_stuck / C_0, benchmarks/cattaneo_mindlin.py) less a margin, so Q* stays below mu P
AMPLITUDE_FACTOR = 1.05


def cycle_scene(q, dt, frequency=CYCLE_FREQUENCY, cycles=CYCLES, **values):
    """The ball held and the base cycled at ``frequency`` for ``cycles`` cycles, for a Q*
    near q mu P (``values``: further scene keys, e.g. contact.k_t)."""
    Q = q * MU * LOAD
    u0 = AMPLITUDE_FACTOR * cm.mindlin_displacement(Q, MU, LOAD, hertz_radius(), E, NU)
    return pull_scene(MU, cycles / frequency, dt, **{
        "drive.v_d": HELD_SPEED, "vibration.f": frequency, "vibration.t_on": 0.0,
        "vibration.k_v": 2.0 * math.pi * frequency * u0 / HELD_SPEED,
        "time.average_cycles": 1, **values})


def cycle_dissipation(result, frequency=CYCLE_FREQUENCY, before=0.0):
    """(Q*, W): over the run's last whole cycle (the last 1 / f of the averaged rows, the
    run at least 1.25 cycles long; with ``before`` the cycle that ends that many cycles
    before the run's end, its start still past the first quarter), the tangential load's
    amplitude (half its peak-to-peak, N) and the loop's area W = |oint Q d(x - x_b)|
    (trapezoids over every step's row, J): the work the holder's force Q does on the
    ball's displacement relative to the base, which only the slip dissipates (the bulk
    is elastic; the damping's share at 500 Hz is ~3e-6 of the top mode's 6%). Q and
    x - x_b are averaged over one period of the ball's ringing (as the pull's,
    quasi_static: +-1.3 N on Q* ~ 30 N otherwise), the strongest line of Q above ten
    times the cycle's frequency."""
    s = result.series
    row = s.t[1] - s.t[0]
    spectrum = np.abs(np.fft.rfft(s.F_d - s.F_d.mean()))
    frequencies = np.fft.rfftfreq(s.F_d.size, row)
    fast = frequencies > 10.0 * frequency
    rows = max(1, int(round(1.0 / frequencies[fast][spectrum[fast].argmax()] / row)))
    window = np.ones(rows) / rows
    t, Q, relative = (np.convolve(y, window, "valid") for y in (s.t, s.F_d, s.x - s.x_b))
    if s.t[-1] < (1.25 + before - 1e-6) / frequency:
        raise ValueError(f"a run of {s.t[-1]:g} s holds no whole cycle at {frequency:g} Hz "
                         f"after its first quarter, {before:g} cycles before its end")
    end = t[-1] - before / frequency
    cycle = (t >= end - 1.0 / frequency - 0.5 * row) & (t <= end + 0.5 * row)
    Q, relative = Q[cycle], relative[cycle]
    return 0.5 * (Q.max() - Q.min()), abs(float(np.trapz(Q, relative)))


def presliding_loop(Q_amplitude, k_t=K_T) -> float:
    """The energy the Dahl law itself dissipates per cycle in Mindlin's stick circle, J:
    what the law's pre-sliding adds to the slip's loop (an estimate on the closed forms).

    A node of Coulomb force F_c = mu N_i and share k_t w_i cycled between -phi F_c and
    phi F_c follows Dahl's branches (exponent 1) F = -+F_c +- (1 + phi) F_c
    exp(-|x - x*| / s_c), s_c = F_c / (k_t w_i), whose loop encloses
    4 F_c s_c (artanh phi - phi) (~ 4/3 F_c s_c phi^3 for small phi). Summed over the
    stick circle with Mindlin's traction ratio phi(r) = 1 - sqrt((c^2 - r^2) / (a^2 - r^2))
    at Q*, the Hertz pressure and w_i = a_i / (pi a^2):

        W_D = 4 mu^2 pi a^2 / k_t  int_0^c p(r)^2 (artanh phi - phi) 2 pi r dr.

    (The slipping annulus is the closed form's own loss.)"""
    from scipy.integrate import quad

    a = hertz_radius()
    p0 = 1.5 * LOAD / (math.pi * a * a)
    c = cm.stick_radius(Q_amplitude, MU, LOAD, a)

    def integrand(r):
        phi = min(1.0 - math.sqrt((c * c - r * r) / (a * a - r * r)), 1.0 - 1e-15)
        return p0 ** 2 * (1.0 - (r / a) ** 2) * (math.atanh(phi) - phi) * 2.0 * math.pi * r

    return 4.0 * MU ** 2 * math.pi * a * a / k_t * quad(integrand, 0.0, c, limit=200)[0]
