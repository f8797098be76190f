"""``vibrofric bench``: wall time against error, every method side by side in one run.

The scene is the paper's Fig 7 case (scenes/longitudinal.toml: k_v = 6, 0.3 s
simulated). Each method's answer, F_dv/F_d0, is compared with a converged
reference of the *same* model:

- the analytic stepper (paper and exact Dahl updates, several dt) against the
  exact-update stepper at plan.analytic_reference_dt (100x below the finest
  step measured; its own error is below 1e-6);
- the FE model (integrators x dt, and mesh levels) against the FE reference
  plan.fe_reference: the explicit integrator at the smallest step on the
  finest mesh of the plan. Its own time-step error is bounded by the gap to
  the explicit run at twice its step (a row of the table);

and, separately, every FE answer against the analytic reference: the lumped
model's own error (the block's compliance and rocking, docs/model.md).

It also measures how the cost grows, on a short vibrated run (GROWTH: the
vibration from 1 ms, F_dv over 20 cycles): the time loop's wall time per
simulated second against DOFs over the mesh levels (explicit at each level's
own stable step, implicit and reduced at a fixed step), and against
simulated time on one mesh, each with the fitted power-law exponent. The
set-up (the model's assembly, the factorization, the reduction) is reported
beside the loop: it is paid once a run, so it is not part of either slope.

Timings are of one core: the bench runs everything in this process, one
run after another, after compiling every loop once (warm_up).

The package, by idea:

    plans                 what a run measures: the scene, the laws, QUICK and FULL
    measuring             one run of each method, timed; measure(plan): all of a plan
    fits                  power-law exponents, Richardson extrapolation, relative errors
    report                the Markdown tables and the speed-against-error plot
    machine               this machine's roofline: bandwidth and multiply-add rate
    step_breakdown        an FE step in parts, each against its roofline bound
    periodic_vs_transient the periodic solver's savings against the transient
"""

from .measuring import measure
from .plans import FULL, QUICK, Plan
from .report import markdown, plot

__all__ = ["FULL", "Plan", "QUICK", "markdown", "measure", "plot"]
