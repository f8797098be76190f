# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # Fig. 9: the drive force against k_v under transverse vibration
#
# The paper's Fig. 9: $F_{dv}/F_{d0}$ against $k_v$ with the base vibrating
# across the sliding direction ($\theta$ = 270°), for the transverse model
# [24], the new model and Abaqus. Unlike longitudinal vibration, transverse
# vibration lowers the drive force already for $k_v < 1$. The new model with
# $\theta$ = 270° is the transverse model [24] (with its transfer coefficient
# $\eta_y$ = 0.71), so one curve stands for both here; the FE model and the
# rigid-Coulomb limit beside it.
#
# `VIBROFRIC_FAST=1`: a reduced grid over a shorter time, without FE;
# `VIBROFRIC_FE=0`: without FE.

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
# The paper's transverse case (a 2 kg block, 3 kHz, $F_N$ = 50.8 N,
# $k_t$ = 67.29 MN/m) is the shipped scene `transverse`.

# %%
scene = vf.load_scene("transverse", **({"time.T": 0.2} if FAST else {}))
k_v = [0.5, 2.0, 20.0] if FAST else [float(k) for k in np.linspace(0, 20, 41)]
coupled = vf.sweep(scene, {"vibration.k_v": k_v})

# %%
fe = None
if WITH_FE:
    fe_scene = scene.with_values({"fem.integrator": "reduced", "time.dt": 1e-5,
                                  "time.steady_tolerance": 2e-3, "fem.output_every": 0})
    fe = vf.sweep(fe_scene, {"vibration.k_v": [0.5, 2.0, 4.0, 6.0, 10.0, 20.0]}, fe=True)

# %%
fig, ax = plt.subplots(figsize=(8, 5))
fine = np.linspace(1e-3, max(k_v), 200)
theta, eta_y = scene.vibration.theta_deg, scene.contact.eta_y
ax.plot(fine, [coulomb_ratio(k, theta, eta_y) for k in fine], "k:", lw=1, label="rigid Coulomb limit")
ax.plot(coupled["vibration.k_v"], coupled["F_dv_over_F_d0"], "s-", ms=3,
        label=r"new model = transverse model [24] (coupled stepper, $\theta$ = 270°)")
if fe is not None:
    ax.plot(fe["vibration.k_v"], fe["fe.F_dv_over_F_d0"], "^", ms=8, label="FE model (reduced, 1e-5 s)")
ax.set(xlabel=r"$k_v = v_a / v_d$", ylabel=r"$F_{dv} / F_{d0}$", ylim=(0, 1.15), xlim=(0, max(k_v)))
ax.legend(fontsize=9, loc="upper right")
fig.suptitle(r"Fig. 9. Change in $F_{dv}/F_{d0}$ as $k_v$ increases in transverse vibration")
fig.tight_layout()
fig.savefig(OUT / "fig09.png", dpi=120)
plt.close(fig)
