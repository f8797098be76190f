"""An answer as a person reads it: F_dv/F_d0 with its error and step, and the warning
where the error exceeds the accuracy asked (time.accuracy).

For the printed lines of ``vibrofric analytic`` and ``vibrofric run`` (cli.py), the
analytic and the FE models alike: both summaries carry the keys of
core.step_error.StepError.as_dict() (error_estimate, dt_used, error_note) and
accuracy, dt_for_accuracy (analytic/accuracy.py). Light: no numpy.
"""

import math


def _error_digits(error: float) -> tuple:
    """(text, decimals): ``error`` rounded up (a bound stays a bound) to one significant
    digit, two where the first is 1 or 2 (0.12, not 0.2), and the decimals of its last
    digit."""
    exponent = math.floor(math.log10(error))
    digits = 2 if error / 10.0**exponent < 3.0 else 1
    unit = 10.0 ** (exponent - digits + 1)
    rounded = math.ceil(error / unit * (1 - 1e-12)) * unit
    decimals = max(0, digits - 1 - exponent)
    if exponent < -4 or exponent > 0:
        return f"{rounded:.{digits - 1}e}", decimals
    return f"{rounded:.{decimals}f}", decimals


def value_with_error(summary: dict, with_step: bool = True) -> str:
    """``0.13701 ± 2e-05 (dt 1e-06 s)``: F_dv/F_d0 to the decimal of its error's last
    digit (at least 4 decimals), the error rounded up (_error_digits), and the step the
    answer was computed at (``with_step``: else the caller says it); "none" where there
    is no ratio, and the reason where no error was estimated."""
    ratio = summary.get("F_dv_over_F_d0")
    if ratio is None:
        return "none"
    error = summary.get("error_estimate")
    dt = summary.get("dt_used") if with_step else None
    step = f"dt {dt:.6g} s" if dt is not None else ""
    if error is None or not math.isfinite(error) or error <= 0.0:
        why = summary.get("error_note") or "no error estimate"
        return f"{ratio:.4f} ({step}; {why})" if step else f"{ratio:.4f} ({why})"
    text, decimals = _error_digits(error)
    return f"{ratio:.{max(4, decimals)}f} ± {text}" + (f" ({step})" if step else "")


def answer_with_error(summary: dict) -> str:
    """``F_dv/F_d0 = 0.13701 ± 2e-05 (dt 1e-06 s)`` (value_with_error)."""
    return f"F_dv/F_d0 = {value_with_error(summary)}"


def accuracy_warning(summary: dict, label: str = "") -> str | None:
    """One line for stderr where the answer's error estimate exceeds time.accuracy,
    naming the step that would meet it; None where it is met (or not estimated)."""
    error, accuracy = summary.get("error_estimate"), summary.get("accuracy")
    if error is None or accuracy is None or error <= accuracy:
        return None
    what = f"{label} " if label else ""
    step, mesh = summary.get("dt_for_accuracy"), summary.get("mesh_error_estimate")
    if step is not None:
        advice = f"; time.dt = {step:.6g} s would meet it"
    elif mesh is not None and mesh >= accuracy:
        advice = f"; the mesh's error alone is {mesh:.2g}: a finer fem.mesh would lower it"
    else:
        advice = ""
    return (f"warning: the {what}answer's step error {error:.2g} exceeds time.accuracy "
            f"{accuracy:g} (dt {summary['dt_used']:.6g} s){advice}")
