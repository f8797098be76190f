"""A sweep under mpirun: the ranks share the grid's points.

Each rank runs its share one point after another, every FE run on a
communicator of its own (fem.run_fe's default, MPI.COMM_SELF): the points are
independent, so N ranks run N points at a time, on one workstation or across
the nodes of a cluster allocation. Rank 0 alone decides what is left to run,
and writes the sweep's own files at the end.
"""

import os
import signal
import time

# Set by the MPI launchers in every rank they start: Open MPI's mpirun, MPICH's
# Hydra and Slurm's srun (PMI2: PMI_SIZE; PMIx: PMIX_RANK). A plain run has none
# of them and never imports mpi4py.
LAUNCHER_VARIABLES = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK")


def launched() -> bool:
    """Whether an MPI launcher started this process (world() is a communicator)."""
    if not any(variable in os.environ for variable in LAUNCHER_VARIABLES):
        return False
    # OMPI_MCA_ess "singleton": inherited from a parent that initialized Open MPI on
    # its own (a script or test that ran DOLFINx, then started this command): its
    # PMIX_RANK is not a launcher's
    return os.environ.get("OMPI_MCA_ess") != "singleton"


def world():
    """MPI.COMM_WORLD if an MPI launcher started this process (launched()), else None.

    Even a world of one rank (``mpirun -n 1``) is used as such: a process pool
    started from an MPI rank would inherit the launcher's variables and its
    workers would take themselves for that rank.
    """
    if not launched():
        return None
    from mpi4py import MPI

    return MPI.COMM_WORLD


def end_with_launcher() -> None:
    """SIGTERM this rank when the process that started it (mpirun, its daemon or
    srun's step daemon) dies, even by SIGKILL: a rank left alone would run its
    share to the end (and rank 0 wait for the others until a broken pipe).
    SIGTERM, not SIGKILL: the rank stops as on any SIGTERM (parallel.interruptible),
    its point in flight cleared. Not for a process without a launcher (its parent
    is init: nothing to follow)."""
    from ..parallel import die_with

    parent = os.getppid()
    if parent > 1:
        die_with(parent, signal.SIGTERM)


def share(points: list, comm) -> list:
    """This rank's points: every size-th one from its rank on, so that neighbouring
    points (similar cost) go to different ranks."""
    return points[comm.rank::comm.size]


def wait_for_all(comm, poll_s: float = 0.2) -> None:
    """A barrier that sleeps rather than spins (Open MPI's busy-waits, taking a
    core from ranks still running) and lets SIGTERM / Ctrl-C through meanwhile."""
    request = comm.Ibarrier()
    while not request.Test():
        time.sleep(poll_s)
