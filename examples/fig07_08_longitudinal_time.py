# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # Figs. 7 and 8: drive force and friction force in time, longitudinal vibration, $k_v$ = 6
#
# The paper's Fig. 7 shows the drive force $F_d$ from rest to 0.3 s: it rises
# with the drive spring until breakaway ($F_d$ reaches $\mu F_N$ = 5.5 N near
# 0.12 s) and falls once the base vibrates (from 0.14 s). Fig. 8 shows the
# friction force $F_x$ over the last cycles, 0.2990-0.3000 s. Both compare the
# longitudinal model [23], the new model and Abaqus; here the 1D stepper, the
# coupled stepper and the FE model.
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
scene = vf.load_scene("longitudinal", **{"time.T": 0.2 if FAST else 0.3,
                                         "time.method": "transient"})
runs = {
    "longitudinal model [23] (1D stepper)": vf.run_analytic(scene, stepper="longitudinal"),
    "new model (coupled stepper)": vf.run_analytic(scene),
}

# %% [markdown]
# The FE model with the reduced integrator at the paper's Abaqus step (1e-5 s):

# %%
if WITH_FE:
    fe_scene = scene.with_values({"fem.integrator": "reduced", "time.dt": 1e-5,
                                  "fem.output_every": 0})
    runs["FE model (reduced, 1e-5 s)"] = vf.run_fe(fe_scene)

for label, run in runs.items():
    print(f"{label}: F_dv/F_d0 = {run.F_dv_over_F_d0:.4f}")

# %% [markdown]
# Each run's `timeseries` is a DataFrame of its kept rows: one every
# `time.series_dt` (1e-5 s) and every step of the last vibration cycles.

# %%
styles = ["-", "--", "-"]
fig, ax = plt.subplots(figsize=(8, 5.5))
for (label, run), style in zip(runs.items(), styles):
    rows = run.timeseries
    ax.plot(rows["t"], rows["F_d"], style, lw=0.8, label=label)
ax.axhline(scene.F_c, color="k", ls=":", lw=0.8, label=r"$\mu F_N$")
ax.axvline(scene.vibration.t_on, color="grey", ls="--", lw=0.8, label="vibration on")
ax.set(xlabel="time t (s)", ylabel="drive force $F_d$ (N)", xlim=(0, scene.time.T))
ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
fig.suptitle(r"Fig. 7. Comparison of change in $F_d$ when longitudinal vibration is switched on, $k_v$ = 6")
fig.tight_layout()
fig.savefig(OUT / "fig07.png", dpi=120)
plt.close(fig)

# %%
last = 1e-3  # s: the paper's window, 0.2990-0.3000 s (4 cycles at 4 kHz)
fig, ax = plt.subplots(figsize=(8, 5.5))
for (label, run), style in zip(runs.items(), styles):
    rows = run.timeseries[run.timeseries["t"] >= scene.time.T - last - 1e-12]
    ax.plot(rows["t"], rows["F_x"], style, lw=1.2, label=f"$F_x$, {label}")
ax.set(xlabel="time t (s)", ylabel="friction force $F_x$ (N)")
ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
fig.suptitle(r"Fig. 8. Comparison of friction force changes during longitudinal vibration, $k_v$ = 6")
fig.tight_layout()
fig.savefig(OUT / "fig08.png", dpi=120)
plt.close(fig)
