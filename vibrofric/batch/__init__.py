"""Batch studies: a grid of scenes run to disk, resumable, on both cores or over MPI.

One idea per module:

    points  a grid point: its directory, running it into that directory
            (results or error, written whole), reading it back
    ledger  the finished points as their directories hold them; results.csv
    mpi     under mpirun: the ranks share the points
    study   run_sweep(): the whole sweep, its progress bar and its report
    in_memory  sweep(): the analytic stepper over a grid, results as a list,
            nothing written (scripts, tests, benchmarks)

DOLFINx and mpi4py are imported only where an FE run or mpirun needs them.
"""

from .in_memory import sweep
from .study import Outcome, run_sweep

__all__ = ["Outcome", "run_sweep", "sweep"]
