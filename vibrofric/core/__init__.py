"""What the analytic and the FE models share, below both of them:

    series       the recorded time series (TimeSeries), which steps a run keeps
                 (RecordPlan) and which of them it writes (written), the averaging
                 window of F_dv (eqs 40-41)
    base_motion  the vibrating base (eqs 23-25), compiled
    friction     the scene's friction law as the steppers take it: kernel
                 arguments, divergence bound, slip-resolving step
    errors       NumericalError, and the refusals (Refusal) of a scene a model cannot run
"""
