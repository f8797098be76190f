"""Process pools that stop at once on Ctrl-C or SIGTERM.

Ctrl-C reaches every process of the terminal's process group; SIGTERM (kill,
a batch scheduler's time limit) often only the parent. Either way the parent
alone decides: its workers ignore Ctrl-C, interruptible() turns both signals
into KeyboardInterrupt in the parent, and on the way out the parent terminates
its workers rather than wait for their tasks (an FE run can take minutes). A
task cut short must therefore leave nothing that looks finished: write its
results with output.staged().
"""

import contextlib
import ctypes
import os
import signal
import sys

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


def default_workers() -> int:
    """Both cores of a workstation: one process per core, two at most by default,
    as FE runs on more processes than cores only slow each other down."""
    return min(2, os.cpu_count() or 1)


PR_SET_PDEATHSIG = 1  # linux/prctl.h


def _die_with(parent: int) -> None:
    """End this worker when ``parent`` dies, however it dies (kill -9 included):
    Linux's parent-death signal, and a check that the parent has not already
    gone before it was set."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent:
        os._exit(1)


def _worker_start(parent: int):
    """In each worker: it dies with its parent (_die_with); Ctrl-C is the
    parent's to handle, and SIGTERM, which only the parent sends a worker, ends
    it at once (a forked worker would otherwise inherit interruptible()'s
    handler and carry on with its next task)."""
    _die_with(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _start_method() -> str:
    """Fork (quick, and scripts need no ``__main__`` guard), unless this process
    has initialized MPI (DOLFINx ran in it: a test session), which a forked
    child must not inherit: then start the workers afresh."""
    mpi = sys.modules.get("mpi4py.MPI")
    return "spawn" if mpi is not None and mpi.Is_initialized() else "fork"


def run_on_pool(function, tasks, workers: int, on_result) -> None:
    """``function(task)`` for every task on ``workers`` processes, one task per
    process at a time; ``on_result(task, result)`` in the parent as each ends,
    which may return further tasks (an iterable), run on the same pool.

    An exception from a task, or an interrupt, ends the whole pool.
    """
    import multiprocessing  # here: every command imports this module, few start a pool
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context(_start_method()),
                               initializer=_worker_start, initargs=(os.getpid(),))
    try:
        futures = {pool.submit(function, task): task for task in tasks}
        while futures:
            done, _ = wait(futures, return_when=FIRST_COMPLETED)
            for future in done:
                task = futures.pop(future)
                for follow in on_result(task, future.result()) or ():
                    futures[pool.submit(function, follow)] = follow
    except BaseException:
        # Python 3.14's ProcessPoolExecutor.terminate_workers() does this.
        for process in list(pool._processes.values()):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()
