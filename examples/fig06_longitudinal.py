# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # Fig. 6: the drive force against k_v under longitudinal vibration
#
# The paper's Fig. 6 plots the cycle-averaged drive force $F_{dv}$, relative to
# the drive force of steady sliding without vibration $F_{d0}$, against
# $k_v = v_a / v_d$ for a base vibrating along the sliding direction
# ($\theta = 0$): the longitudinal model [23], the new coupled model
# (Matlab/Simulink) and a few Abaqus runs. Here: the 1D longitudinal stepper,
# the coupled stepper, the FE model at a few points, and the rigid-Coulomb
# limit $F/F_c = (2/\pi) \arcsin(1/k_v)$ that the Dahl results approach as the
# contact stiffens.
#
# Run it with `python examples/fig06_longitudinal.py` (or `make figures`);
# `VIBROFRIC_FAST=1` runs a reduced grid over a shorter time (the test suite
# does), `VIBROFRIC_FE=0` leaves the FE points out.

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import vibrofric as vf
from vibrofric.analytic.closed_form import coulomb_ratio

FAST = os.environ.get("VIBROFRIC_FAST") == "1"
WITH_FE = os.environ.get("VIBROFRIC_FE", "1") == "1" and not FAST
OUT = Path(os.environ.get("VIBROFRIC_FIGURES", "results/figures"))
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# The paper's longitudinal case (0.5 kg block, 4 kHz, $\mu$ = 0.1,
# $F_N$ = 55 N, 1 s at $\Delta t$ = 1e-6 s, vibration from 0.14 s) ships
# with the package as the scene `longitudinal`.

# %%
scene = vf.load_scene("longitudinal", **({"time.T": 0.2} if FAST else {}))
k_v = [0.5, 2.0, 6.0] if FAST else [float(k) for k in np.linspace(0, 20, 41)]

# %% [markdown]
# The coupled stepper over the grid, both cores (a pandas DataFrame, one row a
# point), and the 1D model [23] point by point:

# %%
coupled = vf.sweep(scene, {"vibration.k_v": k_v})
one_d = [vf.run_analytic(scene.with_values({"vibration.k_v": k}), stepper="longitudinal").F_dv_over_F_d0
         for k in k_v]

# %% [markdown]
# FE points where the paper had Abaqus ones: the reduced integrator at the
# paper's Abaqus step, 1e-5 s, each run stopped once its average has settled.

# %%
fe = None
if WITH_FE:
    fe_scene = scene.with_values({"fem.integrator": "reduced", "time.dt": 1e-5,
                                  "time.steady_tolerance": 2e-3, "fem.output_every": 0})
    fe = vf.sweep(fe_scene, {"vibration.k_v": [1.0, 2.0, 4.0, 6.0, 10.0, 20.0]}, fe=True)

# %%
fig, ax = plt.subplots(figsize=(8, 5))
fine = np.linspace(1e-3, max(k_v), 200)
ax.plot(fine, [coulomb_ratio(k, 0.0, scene.contact.eta_y) for k in fine], "k:", lw=1,
        label="rigid Coulomb limit")
ax.plot(k_v, one_d, "o", ms=6, mfc="none", label="longitudinal model [23] (1D stepper)")
ax.plot(coupled["vibration.k_v"], coupled["F_dv_over_F_d0"], "s-", ms=3,
        label="new model (coupled stepper)")
if fe is not None:
    ax.plot(fe["vibration.k_v"], fe["fe.F_dv_over_F_d0"], "^", ms=8, label="FE model (reduced, 1e-5 s)")
ax.set(xlabel=r"$k_v = v_a / v_d$", ylabel=r"$F_{dv} / F_{d0}$", ylim=(0, 1.15), xlim=(0, max(k_v)))
ax.legend(fontsize=9, loc="upper right")
fig.suptitle(r"Fig. 6. Change in $F_{dv}/F_{d0}$ as $k_v$ increases in longitudinal vibration")
fig.tight_layout()
fig.savefig(OUT / "fig06.png", dpi=120)
plt.close(fig)
