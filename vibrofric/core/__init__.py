"""What the analytic and the FE models share, below both of them:

    series       the recorded time series (TimeSeries), which steps a run keeps
                 (RecordPlan) and which of them it writes (written), the averaging
                 window of F_dv (eqs 40-41)
    base_motion  the vibrating base (eqs 23-25), compiled
    law_limits   the friction law's limits every stepper checks: the force past which
                 an update has diverged, the sliding length, the slip-resolving step
    errors       NumericalError, and the refusals (Refusal) of a scene a model cannot run
    shooting     the periodic steady state as both models' solvers shoot for it: the
                 Orbit, its Floquet multipliers, Newton-Picard for the FE state
"""
