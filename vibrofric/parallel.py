"""Process pools that stop at once on Ctrl-C or SIGTERM.

Ctrl-C reaches every process of the terminal's process group; SIGTERM (kill,
a batch scheduler's time limit) often only the parent. Either way the parent
alone decides: its workers ignore Ctrl-C, interruptible() turns both signals
into KeyboardInterrupt in the parent, and on the way out the parent terminates
its workers rather than wait for their tasks (an FE run can take minutes). A
task cut short must therefore leave nothing that looks finished: write its
results with output.staged().

Also: how many processes a sweep starts (worker_count), and this process's
MPI rank as its launcher set it (launcher_rank: only rank 0 speaks).
"""

import contextlib
import ctypes
import os
import signal
import sys
import threading

_received = None  # the signal that arrived within interruptible(), by name


@contextlib.contextmanager
def interruptible():
    """Within: Ctrl-C and SIGTERM raise KeyboardInterrupt in the main thread,
    so that ``finally`` blocks and staged() clean-ups run; and the signal is
    remembered (stop_if_interrupted), as C++ code that calls back into Python
    (DOLFINx building a mesh) can swallow the exception and carry on.

    A Ctrl-C that is ignored (a job started in the background) stays ignored.
    """
    global _received
    _received = None

    def interrupt(signum, frame):
        global _received
        _received = signal.Signals(signum).name
        raise KeyboardInterrupt(_received)

    previous = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}
    for number, handler in previous.items():
        if handler is not signal.SIG_IGN:
            signal.signal(number, interrupt)
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        _received = None  # what arrived was raised within, or by stop_if_interrupted


def stop_if_interrupted() -> None:
    """Raise KeyboardInterrupt if a signal arrived within interruptible(), even
    one whose exception was swallowed: call it before keeping a result that
    such a signal may have cut short."""
    if _received is not None:
        raise KeyboardInterrupt(_received)


# This process's rank, as MPI launchers set it: Open MPI's mpirun, MPICH's Hydra, Slurm's srun
# (PMI2, PMIx); batch.mpi reads the world itself from mpi4py.
RANK_VARIABLES = ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK")


def launcher_rank() -> int | None:
    """This process's rank if an MPI launcher started it, else None: from the
    launcher's variables alone, at once (the command's last words after an
    interrupt, which must not wait for mpi4py or the batch package to load)."""
    if os.environ.get("OMPI_MCA_ess") == "singleton":   # inherited, not a launcher's (batch.mpi.world)
        return None
    for variable in RANK_VARIABLES:
        value = os.environ.get(variable, "")
        if value.isdigit():
            return int(value)
    return None


def default_workers() -> int:
    """Both cores of a workstation: one process per core, two at most by default,
    as FE runs on more processes than cores only slow each other down."""
    return min(2, cores())


def cores() -> int:
    """The cores this process may run on (its CPU affinity: a batch job's share)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


SINGULAR = {"lanes of points": "lane of points", "points": "point"}   # worker_count's ``what``


def worker_count(requested: int | None, side_by_side: int, oversubscribe: bool | None = False,
                 worker_bytes: int = 0, available: int | None = None, what: str = "tasks") -> tuple:
    """(processes to start, a line saying why fewer than ``requested``, or None).

    Never more than ``side_by_side`` (the tasks that can run at once, named
    ``what`` in the line: more processes would wait idle), nor than this machine's cores unless
    ``oversubscribe`` (asked twice: ``--workers N --oversubscribe``; None: it
    cannot be asked for, as in vibrofric.sweep in memory), nor than fit in
    ``available`` bytes of memory at ``worker_bytes`` each, whatever was
    asked. The default (``requested`` None): default_workers().
    """
    wanted = requested or default_workers()
    things = what if side_by_side != 1 else SINGULAR.get(what, what)
    limits = [(max(1, side_by_side), f"the sweep has {side_by_side} {things} to run side by side")]
    if not oversubscribe:
        hint = " (add --oversubscribe to run more)" if oversubscribe is False else ""
        limits.append((cores(), f"this machine has {cores()} cores{hint}"))
    if worker_bytes and available is not None:
        limits.append((max(1, available // worker_bytes),
                       f"memory for {max(1, available // worker_bytes)} at ~"
                       f"{worker_bytes / 2**20:.0f} MiB each is available"))
    count, why = wanted, None
    for limit, reason in limits:
        if limit < count:
            count, why = limit, reason
    if requested is None or count == requested:
        return count, None
    return count, f"vibrofric: --workers {requested}: {count} process{'es' if count > 1 else ''}, as {why}"


PR_SET_PDEATHSIG = 1  # linux/prctl.h


def die_with(parent: int, signum: int = signal.SIGKILL) -> None:
    """Send this process ``signum`` when ``parent`` dies, however it dies (kill -9
    included): Linux's parent-death signal; and end it now if the parent has
    already gone before that was set."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signum)
    if os.getppid() != parent:
        os._exit(1)


def _worker_start(parent: int):
    """In each worker: it dies with its parent (die_with); Ctrl-C is the
    parent's to handle, and SIGTERM, which only the parent sends a worker, ends
    it at once (a forked worker would otherwise inherit interruptible()'s
    handler and carry on with its next task)."""
    die_with(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _start_method() -> str:
    """Fork (quick, and scripts need no ``__main__`` guard), unless this process
    has initialized MPI (DOLFINx ran in it: a test session), which a forked
    child must not inherit: then start the workers afresh."""
    mpi = sys.modules.get("mpi4py.MPI")
    return "spawn" if mpi is not None and mpi.Is_initialized() else "fork"


SIGNAL_LATENCY = 0.1   # s: the longest a Ctrl-C or SIGTERM waits while the pool is watched


@contextlib.contextmanager
def _signals_held():
    """SIGINT and SIGTERM held back (pthread_sigmask) inside the block, delivered as it
    ends. concurrent.futures.wait() holds every future's lock while it registers its
    waiter: a KeyboardInterrupt raised in there leaves one held, and the pool's
    manager thread, failing the futures of its terminated workers, then waits on it
    for ever, as does the interpreter's exit (seen once on Python 3.12, a two-worker
    sweep interrupted under load). Held back, the signal is raised once wait() has
    returned."""
    held = {signal.SIGINT, signal.SIGTERM}
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, before)


def run_on_pool(function, tasks, workers: int, on_result) -> None:
    """``function(task)`` for every task on ``workers`` processes, one task per
    process at a time; ``on_result(task, result)`` in the parent as each ends,
    which may return further tasks (an iterable), run on the same pool.

    An exception from a task, or an interrupt, ends the whole pool: its workers
    are terminated, and gone, before this returns (what they were writing is
    then the caller's to clear: output.remove_partials). No more processes are
    started than ``tasks`` (an on_result returns one task at most for the one it
    was given, in every use here): Python starts a forked pool's every process at once.
    """
    import multiprocessing  # here: every command imports this module, few start a pool
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    tasks = list(tasks)
    pool = ProcessPoolExecutor(max(1, min(workers, len(tasks))),
                               mp_context=multiprocessing.get_context(_start_method()),
                               initializer=_worker_start, initargs=(os.getpid(),))
    try:
        futures = {pool.submit(function, task): task for task in tasks}
        while futures:
            with _signals_held():
                done, _ = wait(futures, timeout=SIGNAL_LATENCY, return_when=FIRST_COMPLETED)
            for future in done:
                task = futures.pop(future)
                for follow in on_result(task, future.result()) or ():
                    futures[pool.submit(function, follow)] = follow
    except BaseException:
        # Python 3.14's ProcessPoolExecutor.terminate_workers() does this.
        processes = list(pool._processes.values())
        for process in processes:
            process.terminate()
        for process in processes:   # gone, so that nothing writes after this returns
            process.join(timeout=5)
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()
