# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # Fig. 12: the drive force against the vibration angle, coupled vibration
#
# The paper's Fig. 12: $F_{dv}/F_{d0}$ against the angle $\theta$ of the
# vibration to the sliding direction, at $k_v$ = 2, 3, 4, 6 and 20, 25 angles
# each (the new model in Matlab/Simulink), 3 further Abaqus runs per $k_v$,
# and the LuGre law at $k_v$ = 2 and 20 with $h_t = h_v$ = 0 and
# $F_s = \mu F_N$, which reduces to Dahl: an exact match. Larger $k_v$ lowers
# the drive force at every angle; the greatest reduction is always
# longitudinal (0°, 180°), and the curve is symmetric about 180°.
#
# `VIBROFRIC_FAST=1`: fewer angles and $k_v$ values over a shorter time,
# without FE; `VIBROFRIC_FE=0`: without FE.

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import vibrofric as vf

FAST = os.environ.get("VIBROFRIC_FAST") == "1"
WITH_FE = os.environ.get("VIBROFRIC_FE", "1") == "1" and not FAST
OUT = Path(os.environ.get("VIBROFRIC_FIGURES", "results/figures"))
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# The shipped scene `coupled` is the paper's Fig. 12 case (the transverse
# case's block and contact, any angle).

# %%
scene = vf.load_scene("coupled", **({"time.T": 0.2} if FAST else {}))
k_v = [2.0, 20.0] if FAST else [2.0, 3.0, 4.0, 6.0, 20.0]
angles = [float(a) for a in np.linspace(0, 360, 9 if FAST else 25)]
dahl = vf.sweep(scene, {"vibration.k_v": k_v, "vibration.theta_deg": angles})

# %% [markdown]
# LuGre with $h_t = h_v = 0$ and the stiction force at its default, $\mu F_N$:

# %%
lugre_scene = vf.load_scene(scene, **{"contact.law": "lugre"})
lugre = vf.sweep(lugre_scene, {"vibration.k_v": [k_v[0], k_v[-1]], "vibration.theta_deg": angles})

# %% [markdown]
# FE points, three angles per $k_v$ as the paper's Abaqus runs: the reduced
# integrator at 1e-5 s, each run stopped once its average has settled.

# %%
fe = None
if WITH_FE:
    fe_scene = scene.with_values({"fem.integrator": "reduced", "time.dt": 1e-5,
                                  "time.steady_tolerance": 2e-3, "fem.output_every": 0})
    fe = vf.sweep(fe_scene, {"vibration.k_v": k_v, "vibration.theta_deg": [0.0, 45.0, 90.0]}, fe=True)

# %%
fig, ax = plt.subplots(figsize=(9.5, 5))
for i, k in enumerate(k_v):
    colour = f"C{i}"
    rows = dahl[dahl["vibration.k_v"] == k]
    ax.plot(rows["vibration.theta_deg"], rows["F_dv_over_F_d0"], "o-", ms=3, color=colour,
            label=f"$k_v$ = {k:g}, new model (Dahl)")
    rows = lugre[lugre["vibration.k_v"] == k]
    if len(rows):
        ax.plot(rows["vibration.theta_deg"], rows["F_dv_over_F_d0"], "x", ms=7, color=colour,
                label=f"$k_v$ = {k:g}, LuGre ($h_t = h_v$ = 0)")
    if fe is not None:
        rows = fe[fe["vibration.k_v"] == k]
        ax.plot(rows["vibration.theta_deg"], rows["fe.F_dv_over_F_d0"], "s", ms=8, mfc="none",
                mew=1.5, color=colour, label=f"$k_v$ = {k:g}, FE model")
ax.set(xlabel=r"vibration angle $\theta$ (°)", ylabel=r"$F_{dv} / F_{d0}$",
       xticks=range(0, 361, 45), xlim=(-8, 368), ylim=(0, None))
ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
fig.suptitle(r"Fig. 12. Changes in $F_{dv}/F_{d0}$ with $\theta$ at different values of $k_v$")
fig.tight_layout()
fig.savefig(OUT / "fig12.png", dpi=120)
plt.close(fig)
