# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # Figs. 10 and 11: drive force and friction force in time, transverse vibration, $k_v$ = 20
#
# The paper's Fig. 10: the drive force from rest to 0.3 s (breakaway near
# 0.11 s at $\mu F_N$ = 5.08 N, vibration from 0.14 s). Fig. 11: the friction
# force's components over the last cycles, 0.2990-0.3000 s: at $k_v$ = 20,
# $F_x$ changes only in magnitude, $F_y$ in magnitude and direction. Here the
# coupled stepper (the new model, which along $\theta$ = 270° is the
# transverse model [24]) and the FE model.
#
# `VIBROFRIC_FAST=1`: to 0.2 s, without FE; `VIBROFRIC_FE=0`: without FE.

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt

import vibrofric as vf

FAST = os.environ.get("VIBROFRIC_FAST") == "1"
WITH_FE = os.environ.get("VIBROFRIC_FE", "1") == "1" and not FAST
OUT = Path(os.environ.get("VIBROFRIC_FIGURES", "results/figures"))
OUT.mkdir(parents=True, exist_ok=True)

# %%
# The drive force in time from rest: stepped through the transient (time.method
# "transient"; the default answers by the steady cycle alone).
scene = vf.load_scene("transverse", **{"time.T": 0.2 if FAST else 0.3,
                                       "time.method": "transient"})
runs = {"new model (coupled stepper)": vf.run_analytic(scene)}
if WITH_FE:
    fe_scene = scene.with_values({"fem.integrator": "reduced", "time.dt": 1e-5,
                                  "fem.output_every": 0})
    runs["FE model (reduced, 1e-5 s)"] = vf.run_fe(fe_scene)
for label, run in runs.items():
    print(f"{label}: F_dv/F_d0 = {run.F_dv_over_F_d0:.4f}")

# %%
fig, ax = plt.subplots(figsize=(8, 5.5))
for label, run in runs.items():
    ax.plot(run.timeseries["t"], run.timeseries["F_d"], lw=0.8, label=label)
ax.axhline(scene.F_c, color="k", ls=":", lw=0.8, label=r"$\mu F_N$")
ax.axvline(scene.vibration.t_on, color="grey", ls="--", lw=0.8, label="vibration on")
ax.set(xlabel="time t (s)", ylabel="drive force $F_d$ (N)", xlim=(0, scene.time.T))
ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
fig.suptitle(r"Fig. 10. Comparison of change in $F_d$ when transverse vibration is switched on, $k_v$ = 20")
fig.tight_layout()
fig.savefig(OUT / "fig10.png", dpi=120)
plt.close(fig)

# %%
last = 1e-3  # s: the paper's window, 0.2990-0.3000 s (3 cycles at 3 kHz)
fig, ax = plt.subplots(figsize=(8, 5.5))
for (label, run), style in zip(runs.items(), ["-", "--"]):
    rows = run.timeseries[run.timeseries["t"] >= scene.time.T - last - 1e-12]
    ax.plot(rows["t"], rows["F_x"], style, lw=1.2, color="C0", label=f"$F_x$, {label}")
    ax.plot(rows["t"], rows["F_y"], style, lw=1.2, color="C3", label=f"$F_y$, {label}")
ax.set(xlabel="time t (s)", ylabel="friction force (N)")
ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
fig.suptitle(r"Fig. 11. Comparison of friction force changes during transverse vibration, $k_v$ = 20")
fig.tight_layout()
fig.savefig(OUT / "fig11.png", dpi=120)
plt.close(fig)
