"""A user's law's specialized loops, compiled after its first run, in the background.

A law's first run calls it through a pointer (through_pointer.py), so that it
answers without compiling its loops; the loops it ran that way are listed here
(``schedule``), and when the command ends a process of its own (at the lowest
CPU priority, detached from the terminal) compiles them specialized for the law
into numba's cache, under the same locks as any compile (specialize.ready). A
later run of the law loads them: the linked loops' speed from the second run on.
A run that starts before they are written runs through the pointer again.

    python -m vibrofric.friction_law.specialize_later   # reads the list on stdin

The list: (the kernel's module, its name, the law as load_law takes it, the
numba argument types), pickled. Nothing is printed: a failure leaves the loops
to be compiled by a later run (VIBROFRIC_SPECIALIZE=now) or again in the background.
"""

import atexit
import importlib
import os
import pickle
import subprocess
import sys
from pathlib import Path

from .contract import is_law_file

_pending = []


def schedule(kernel, law, sig: tuple) -> None:
    """Compile ``kernel`` for ``law`` and the argument types ``sig`` when this process ends."""
    if not _pending:
        atexit.register(start)
    name = str(Path(law.module.__file__).resolve()) if is_law_file(law.name) else law.name
    _pending.append((kernel.py_func.__module__, kernel.__name__, name, sig))


def start() -> None:
    """Start the background compile of what ``schedule`` listed (at exit)."""
    if not _pending:
        return
    listed = pickle.dumps(list(_pending))
    _pending.clear()
    try:
        child = subprocess.Popen([sys.executable, "-m", __name__], stdin=subprocess.PIPE,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                 start_new_session=True, env=_environment())
        child.stdin.write(listed)
        child.stdin.close()
    except OSError:
        pass


def _environment() -> dict:
    """This process's environment, with the package it runs on PYTHONPATH's front (the
    same sources: the same fingerprints)."""
    root = str(Path(__file__).resolve().parent.parent.parent)
    path = os.environ.get("PYTHONPATH", "")
    return {**os.environ, "PYTHONPATH": root + (os.pathsep + path if path else "")}


def compile_listed(listed) -> None:
    """Compile each (module, kernel, law, types) specialized for the law (cached)."""
    from .contract import load_law
    from .specialize import ready, unannounced

    with unannounced():
        for module, name, law_name, sig in listed:
            kernel = getattr(importlib.import_module(module), name)
            law = load_law(law_name)
            ready(kernel.for_law(law), sig, f"{name} for {law_name}")


if __name__ == "__main__":
    try:
        os.nice(19)
    except OSError:
        pass
    compile_listed(pickle.loads(sys.stdin.buffer.read()))
