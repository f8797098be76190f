"""PNG plots: the paper's figures for a run and for a sweep.

Figures are made on an Agg canvas of their own (matplotlib.figure.Figure), not
through pyplot: nothing global to close, and importing this module costs
matplotlib and numpy only (not pyplot, nor the stepper's numba), so that
plot_worker's process is ready to draw soon after it starts.

The two figures of a run read of the scene only ``name``, ``F_c``,
``vibrated`` and ``vibration.f``, ``.k_v``, ``.theta_deg``, ``.t_on``
(plot_worker.plotted_scene sends these to its process).
"""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .core.series import PLOT_CYCLES

LIMIT_POINTS = 80  # on the rigid Coulomb limit's curve; each point is a quadrature
# Every analytic run draws the two figures of a run, which would otherwise take
# longer than its stepping: fixed margins instead of tight_layout (a second text
# layout pass; these fit tick labels of up to five digits), and PNG compressed at
# zlib level 1 (the file ~20% larger; docs/performance.md, "Design choices measured").
# The figure is made at the PNG's resolution, so that saving it lays out no text anew.
RUN_MARGINS = {"left": 0.12, "right": 0.98, "bottom": 0.14, "top": 0.91}
RUN_DPI = 120
RUN_PNG = {"dpi": RUN_DPI, "pil_kwargs": {"compress_level": 1}}


def figure(figsize, dpi=None):
    """(Figure, Axes) on an Agg canvas of their own; dropped, not closed, when done."""
    fig = Figure(figsize=figsize, dpi=dpi)
    FigureCanvasAgg(fig)
    return fig, fig.subplots()


# A stepped run's history is drawn sample by sample up to this many vibration cycles;
# beyond, its cycles are closer than a line's width on a 7-inch plot (the Fig 7 scene
# to 0.3 s has 640): each cycle is drawn as its mean and its range (cycle_envelope).
DRAWN_CYCLES = 60


def cycle_envelope(t, y, f: float, t_on: float):
    """(t, low, mean, high) of ``y`` over each whole vibration cycle from ``t_on`` on
    (cycle k: t_on + k / f <= t < t_on + (k + 1) / f), t each cycle's middle: what a
    history of too many cycles to draw shows. From the rows given (a written series
    has at least core.series.ROWS_PER_CYCLE a cycle, so the range is the sampled one,
    within a few % of the swing)."""
    t, y = np.asarray(t), np.asarray(y)
    cycle = np.floor((t - t_on) * f + 1e-9).astype(np.int64)
    on = t >= t_on
    cycles, first = np.unique(cycle[on], return_index=True)
    ends = np.append(first[1:], on.sum())
    values = y[on]
    low = np.array([values[a:b].min() for a, b in zip(first, ends)])
    high = np.array([values[a:b].max() for a, b in zip(first, ends)])
    mean = np.array([values[a:b].mean() for a, b in zip(first, ends)])
    return t_on + (cycles + 0.5) / f, low, mean, high


def _history(ax, t, y, scene, label):
    """y against t: as it is while few enough cycles are in view (DRAWN_CYCLES), else
    as it is before the vibration and as the mean and range of each cycle after."""
    t, y = np.asarray(t), np.asarray(y)
    vibration = scene.vibration
    if not scene.vibrated or (t[-1] - max(t[0], vibration.t_on)) * vibration.f <= DRAWN_CYCLES:
        return ax.plot(t, y, lw=0.8, label=label)[0]
    before = t < vibration.t_on
    middle, low, mean, high = cycle_envelope(t, y, vibration.f, vibration.t_on)
    line, = ax.plot(np.append(t[before], middle), np.append(y[before], mean), lw=0.8,
                    label=f"{label} (mean and range of each cycle)")
    ax.fill_between(middle, low, high, color=line.get_color(), alpha=0.3, lw=0)
    return line


def steady_phase(t, f: float):
    """(phase in degrees, which rows) of the last base cycle of a series ``t`` that ends
    with a steady cycle: phase 0 at its start, where the base is at its centre moving
    forward (u = u0 sin(phase), eq 23), 360 at its end (the series' last row). The
    steady cycle starts at a zero of the base's phase (core/shooting.py), so the
    phase is the time before the end in cycles."""
    t = np.asarray(t)
    rows = t >= t[-1] - (1 + 1e-9) / f
    return 360.0 * (1.0 - (t[-1] - t[rows]) * f), rows


PHASE_LABEL = r"phase of the base, $\varphi$ (°; base at $u_0 \sin\varphi$)"


def _title(scene, what: str) -> str:
    return (f"{scene.name}: $k_v$ = {scene.vibration.k_v:g}, "
            rf"$\theta$ = {scene.vibration.theta_deg:g}°{what}")


def drive_force_figure(runs: dict, scene, steady=()):
    """F_d of each run (``runs`` maps a label to a TimeSeries, or anything with ``t``
    and ``F_d``). Where every run is answered by its steady cycle (their labels in
    ``steady``: each series is a few repeats of the cycle ending at time.T), one cycle
    of each against the base's phase, with each F_dv (the cycle's mean, eq 41): both
    models on the same span. Else F_d over the whole run (Fig 7 / Fig 10 analogue),
    each run's vibrated cycles as their mean and range where too many to draw
    (_history)."""
    fig, ax = figure((7, 4), RUN_DPI)
    if scene.vibrated and runs and set(runs) <= set(steady):
        for label, series in runs.items():
            phase, rows = steady_phase(series.t, scene.vibration.f)
            force = np.asarray(series.F_d)[rows]
            mean = force[1:].mean()   # the cycle's steps: its first row is its last one's
            line, = ax.plot(phase, force, lw=1.0, label=label)
            ax.axhline(mean, color=line.get_color(), ls="--", lw=0.8,
                       label=f"{label}: $F_{{dv}}$ = {mean:.4g} N")
        ax.set(xlabel=PHASE_LABEL, ylabel="drive force $F_d$ (N)", xlim=(0, 360),
               xticks=range(0, 361, 45),
               title=_title(scene, ", the steady cycle ending at $T$"))
    else:
        for label, series in runs.items():
            _history(ax, series.t, series.F_d, scene, label)
        ax.axhline(scene.F_c, color="k", ls=":", lw=0.8, label=r"$F_c = \mu F_N$")
        if scene.vibrated:
            ax.axvline(scene.vibration.t_on, color="grey", ls="--", lw=0.8, label="vibration on")
        ax.set(xlabel="time t (s)", ylabel="drive force $F_d$ (N)", title=_title(scene, ""))
    ax.legend(fontsize=8)
    fig.subplots_adjust(**RUN_MARGINS)
    return fig


def drive_force_history(runs: dict, scene, path, steady=()) -> None:
    """drive_force_figure() as PNG."""
    drive_force_figure(runs, scene, steady).savefig(path, **RUN_PNG)


def friction_last_cycles_figure(runs: dict, scene):
    """F_x and F_y over the last vibration cycles (Fig 8 / Fig 11 analogue). The curves
    sweep the whole height every cycle, so the legend stands below the axes, where it
    hides none of them."""
    fig, ax = figure((7, 4.6), RUN_DPI)
    duration = PLOT_CYCLES / scene.vibration.f
    for label, series in runs.items():
        tail = series.tail(duration)
        ax.plot(tail.t, tail.F_x, lw=1.0, label=f"$F_x$ {label}")
        ax.plot(tail.t, tail.F_y, lw=1.0, ls="--", label=f"$F_y$ {label}")
    ax.set(xlabel="time t (s)", ylabel="friction force (N)",
           title=f"friction over the last {PLOT_CYCLES} cycles")
    ax.legend(fontsize=8, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.15))
    fig.subplots_adjust(**{**RUN_MARGINS, "bottom": 0.28})
    return fig


def friction_last_cycles(runs: dict, scene, path) -> None:
    """friction_last_cycles_figure() as PNG."""
    friction_last_cycles_figure(runs, scene).savefig(path, **RUN_PNG)


def _column(rows: list, key: str) -> np.ndarray:
    """One column of a sweep's rows as floats; a missing ratio (None) becomes NaN."""
    return np.array([r[key] for r in rows], float)


def ratio_against_kv(records: list, scene, path, key="F_dv_over_F_d0", fe_key=None) -> None:
    """F_dv/F_d0 against k_v (Fig 6 / Fig 9 analogue), with the rigid Coulomb limit.

    ``records`` are a sweep's rows, flattened (output.flatten); ``key`` is the
    analytic stepper's ratio, drawn as the curve, and ``fe_key``, if given, the
    FE model's, drawn as markers over it.
    """
    from .analytic.closed_form import coulomb_ratio  # here: vibrofric.analytic imports numba

    k_v = _column(records, "vibration.k_v")
    order = np.argsort(k_v)
    fig, ax = figure((7, 4))
    ax.plot(k_v[order], _column(records, key)[order], "o-", ms=4, label="Dahl stepper")
    if fe_key is not None:
        ax.plot(k_v[order], _column(records, fe_key)[order], "s", ms=7, mfc="none", mew=1.5,
                label="FE model")
    fine = np.linspace(max(k_v.min(), 1e-3), k_v.max(), LIMIT_POINTS)
    limit = [coulomb_ratio(k, scene.vibration.theta_deg, scene.contact.eta_y) for k in fine]
    ax.plot(fine, limit, "k:", lw=1, label="rigid Coulomb limit")
    ax.set(xlabel=r"$k_v = v_a / v_d$", ylabel=r"$F_{dv} / F_{d0}$", ylim=(0, 1.1),
           title=rf"{scene.name}: $\theta$ = {scene.vibration.theta_deg:g}°")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def ratio_against_angle(records: list, path, key="F_dv_over_F_d0", fe_key=None) -> None:
    """F_dv/F_d0 against theta, one curve per k_v (Fig 12 analogue); with
    ``fe_key``, the FE model's values as markers of the same colour. The legend
    stands right of the axes, where it hides no curve."""
    fig, ax = figure((8.2, 4.5))
    for k_v in sorted({r["vibration.k_v"] for r in records}):
        rows = sorted((r for r in records if r["vibration.k_v"] == k_v),
                      key=lambda r: r["vibration.theta_deg"])
        theta = _column(rows, "vibration.theta_deg")
        line, = ax.plot(theta, _column(rows, key), "o-", ms=3, label=f"$k_v$ = {k_v:g}")
        if fe_key is not None:
            ax.plot(theta, _column(rows, fe_key), "s", ms=7, mfc="none", mew=1.5, color=line.get_color())
    if fe_key is not None:
        ax.plot([], [], "ks", ms=7, mfc="none", label="FE model (markers)")
    ax.set(xlabel=r"vibration angle $\theta$ (°)", ylabel=r"$F_{dv} / F_{d0}$",
           xticks=range(0, 361, 45), ylim=(0, None),
           title=r"$F_{dv} / F_{d0}$ against the vibration angle $\theta$, one curve a $k_v$"
                 + (" (lines: analytic stepper)" if fe_key is not None else ""))
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def error_per_point(records: list, keys: list, path) -> None:
    """|FE - analytic| / analytic on F_dv/F_d0 at every point of an FE sweep:
    against the grid's last key, one line per combination of the others."""
    *outer, inner = keys
    fig, ax = figure((7, 4))
    for group in dict.fromkeys(tuple(r[k] for k in outer) for r in records):
        rows = [r for r in records if tuple(r[k] for k in outer) == group]
        label = ", ".join(f"{k.split('.')[-1]} = {v}" for k, v in zip(outer, group)) or None
        ax.plot([r[inner] for r in rows], 100 * _column(rows, "rel_error"), "o-", ms=4, label=label)
    ax.set(xlabel=inner, ylabel="|FE - analytic| / analytic (%)", ylim=(0, None),
           title=r"FE model against the analytic stepper: $F_{dv} / F_{d0}$")
    if outer:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


# The normal forces drawn, by the series' column: (the curve's label, the figure's subject)
NORMAL_FORCES = {
    "F_n": (r"$\sum$ nodal normal force", "normal force over the contact face"),   # FE
    "N": ("contact normal force $N$", "the lumped body's normal force"),          # analytic
}


def normal_force_figure(series, scene, steady: bool = False, column: str = "F_n",
                        lumped=None):
    """A normal force against time (``series.extra[column]``, NORMAL_FORCES): the FE
    model's summed normal reaction (steady at F_N in a sound run), or the lumped body's
    contact force N of a base moving along Z (analytic/normal.py: 0 out of contact).
    ``lumped``: the lumped body's series (its ``extra["N"]``) drawn beside an FE run's
    on the same axes (vibrofric run of a base moving along Z). Runs answered by their
    steady cycle (``steady``: all the drawn ones are): that cycle against the base's
    phase; else over time, vibrated cycles as their mean and range where too many to
    draw (_history)."""
    fig, ax = figure((7, 3.5), RUN_DPI)
    if lumped is None:
        curves = [(series, column, NORMAL_FORCES[column][0])]
        subject = NORMAL_FORCES[column][1]
    else:
        curves = [(series, column, f"FE: {NORMAL_FORCES[column][0]}"),
                  (lumped, "N", f"lumped: {NORMAL_FORCES['N'][0]}")]
        subject = "the normal force, FE and lumped"
    if steady and scene.vibrated:
        for drawn, name, label in curves:
            phase, rows = steady_phase(drawn.t, scene.vibration.f)
            ax.plot(phase, np.asarray(drawn.extra[name])[rows], lw=1.0, label=label)
        ax.set(xlabel=PHASE_LABEL, xlim=(0, 360), xticks=range(0, 361, 45),
               title=f"{subject}, the steady cycle ending at $T$")
    else:
        for drawn, name, label in curves:
            _history(ax, drawn.t, drawn.extra[name], scene, label)
        ax.set(xlabel="time t (s)", title=subject)
    ax.axhline(scene.contact.F_N, color="k", ls=":", lw=0.8, label=r"$F_N$")
    ax.set(ylabel="normal reaction (N)")
    ax.legend(fontsize=8, loc="best")   # the curve may fill any corner
    fig.subplots_adjust(**{**RUN_MARGINS, "bottom": 0.15, "top": 0.9})
    return fig


def normal_force_history(series, scene, path, steady: bool = False, column: str = "F_n",
                         lumped=None) -> None:
    """normal_force_figure() as PNG."""
    normal_force_figure(series, scene, steady, column, lumped).savefig(path, **RUN_PNG)
