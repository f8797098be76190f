# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
# ---

# %% [markdown]
# # Beside Fig. 12: the base moving normal to the contact too
#
# Not in the paper. The Fig. 12 scene (`coupled`, $k_v$ = 6) with its base moving
# along Z as well, $z_b = A_n \sin(\omega t + \varphi)$ beside the in-plane
# $u_0 \sin\omega t$ (docs/model.md section 6, the lumped model). Left:
# $F_{dv}/F_{d0}$ against the in-plane angle $\theta$, one curve per normal
# amplitude $A_n$, as a fraction of the amplitude at which the body would start
# to lose its contact, $A_{loss} = F_N |1 - r^2| / (k_n r^2)$, $r = \omega / \omega_n$
# (the motions in phase, $\varphi$ = 0: a straight line inclined out of the plane).
# Right: against the phase $\varphi$ at $A_n = A_{loss} / 2$, at three angles:
# $\varphi$ = 90° at $\theta$ = 0 is an elliptical motion in the XZ plane.
# The normal force is largest where the base is lowest (below the bounce
# resonance the body follows the base, and its downward acceleration is
# greatest there: $N - F_N = -k_n z_b r^2 / (1 - r^2)$); where that falls while
# the base moves forward, friction carries the body forward (the vibratory
# conveyor), and the drive force can turn negative.
#
# `VIBROFRIC_FAST=1`: fewer angles, amplitudes and phases over a shorter time.
# `--fe` (or `VIBROFRIC_FE=1`): FE points too, a coarse grid (two amplitudes,
# three angles) through the sweep API; they need an FE model whose base moves
# along Z, which the FE model refuses before any work where it does not.

# %%
import math
import os
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import vibrofric as vf

FAST = os.environ.get("VIBROFRIC_FAST") == "1"
WITH_FE = ("--fe" in sys.argv[1:] or os.environ.get("VIBROFRIC_FE") == "1") and not FAST
OUT = Path(os.environ.get("VIBROFRIC_FIGURES", "results/figures"))
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# The amplitude of contact loss, from the undamped forced response in contact
# (the normal force swings by $k_n A_n r^2 / |1 - r^2|$ about $F_N$):

# %%
scene = vf.load_scene("coupled", **({"time.T": 0.2} if FAST else {}))
r = scene.omega / math.sqrt(scene.normal_stiffness / scene.body.mass)
A_loss = scene.contact.F_N * abs(1.0 - r * r) / (scene.normal_stiffness * r * r)
print(f"r = {r:.3f}, A_loss = {A_loss * 1e9:.1f} nm")

fractions = [0.0, 0.5] if FAST else [0.0, 0.25, 0.5, 0.75, 0.95]
angles = [float(a) for a in np.linspace(0, 360, 9 if FAST else 25)]
by_angle = vf.sweep(scene, {"vibration.normal_amplitude": [f * A_loss for f in fractions],
                            "vibration.theta_deg": angles})

# %% [markdown]
# The phase of the normal motion, at half the amplitude of contact loss:

# %%
phase_angles = [0.0, 90.0, 180.0]
phases = [float(p) for p in np.linspace(0, 360, 9 if FAST else 25)]
by_phase = vf.sweep(scene.with_values({"vibration.normal_amplitude": 0.5 * A_loss}),
                    {"vibration.theta_deg": phase_angles, "vibration.normal_phase_deg": phases})

# %% [markdown]
# FE points: the explicit integrator, each run stopped once its average has
# settled; a coarse grid.

# %%
fe = None
if WITH_FE:
    fe_scene = scene.with_values({"time.steady_tolerance": 2e-3, "fem.output_every": 0})
    fe = vf.sweep(fe_scene, {"vibration.normal_amplitude": [0.0, 0.5 * A_loss],
                             "vibration.theta_deg": [0.0, 90.0, 180.0]}, fe=True)
    for _, point in fe.iterrows():   # each FE point beside the lumped answer at it
        lumped = by_angle[np.isclose(by_angle["vibration.normal_amplitude"],
                                     point["vibration.normal_amplitude"])
                          & (by_angle["vibration.theta_deg"] == point["vibration.theta_deg"])]
        print(f"A_n = {point['vibration.normal_amplitude'] * 1e9:.1f} nm, theta = "
              f"{point['vibration.theta_deg']:g}: FE {point['fe.F_dv_over_F_d0']:.4f}, lumped "
              f"{lumped['F_dv_over_F_d0'].iloc[0]:.4f}")

# %%
fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
for i, fraction in enumerate(fractions):
    amplitude = fraction * A_loss
    rows = by_angle[by_angle["vibration.normal_amplitude"] == amplitude]
    left.plot(rows["vibration.theta_deg"], rows["F_dv_over_F_d0"], "o-", ms=3, color=f"C{i}",
              label=rf"$A_n$ = {fraction:g} $A_{{loss}}$ ({amplitude * 1e9:.0f} nm)")
    if fe is not None:
        rows = fe[np.isclose(fe["vibration.normal_amplitude"], amplitude)]
        if len(rows):
            left.plot(rows["vibration.theta_deg"], rows["fe.F_dv_over_F_d0"], "s", ms=8,
                      mfc="none", mew=1.5, color=f"C{i}")
if fe is not None:
    left.plot([], [], "ks", ms=8, mfc="none", label="FE model (markers)")
left.axhline(0.0, color="k", lw=0.5)
left.set(xlabel=r"vibration angle $\theta$ (°)", ylabel=r"$F_{dv} / F_{d0}$",
         xticks=range(0, 361, 45), xlim=(-8, 368),
         title=r"in phase ($\varphi$ = 0), against $\theta$")
left.legend(fontsize=8)
for i, theta in enumerate(phase_angles):
    rows = by_phase[by_phase["vibration.theta_deg"] == theta]
    right.plot(rows["vibration.normal_phase_deg"], rows["F_dv_over_F_d0"], "o-", ms=3,
               color=f"C{i + 5}", label=rf"$\theta$ = {theta:g}°")
right.axhline(0.0, color="k", lw=0.5)
right.set(xlabel=r"phase of the normal motion $\varphi$ (°)", xticks=range(0, 361, 45),
          xlim=(-8, 368), title=r"$A_n = A_{loss} / 2$, against $\varphi$")
right.legend(fontsize=8)
fig.suptitle(rf"Beside Fig. 12: $F_{{dv}}/F_{{d0}}$ with the base moving along Z too "
             rf"($k_v$ = {scene.vibration.k_v:g}, f = {scene.vibration.f:g} Hz, lumped model)")
fig.tight_layout()
fig.savefig(OUT / "fig12_normal.png", dpi=120)
plt.close(fig)
