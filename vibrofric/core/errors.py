"""The errors of the numerics, which the command line reports in words (cli.py)."""


class NumericalError(RuntimeError):
    """A run whose numbers went wrong (NaN, a diverging update); never written as results."""
