"""Time loops compiled for one friction law: the law's update inlined, cached on disk.

A time loop (the lumped steppers, the FE integrators) calls the law as the
global ``law_update`` (and ``law_energy`` for its stored energy). Written with
``@law_kernel(...)`` instead of ``@njit(...)``, a loop is compiled per law:
``loop.for_law(law)`` rebuilds the function with the law's compiled update in
its globals, and every other law kernel it calls rebuilt the same way, then
compiles it with numba, cached on disk under a name that carries
``law.fingerprint`` (the law's source and the package's). So the law is
inlined into the loop as if written there, a second run loads the compiled
loop from the cache, and an edited law or package compiles anew: no stale
compiled code is ever used. Of each loop the KEPT_VERSIONS most recent
compiled versions stay on disk.
"""

import types
from pathlib import Path

from numba import njit

KEPT_VERSIONS = 8  # compiled versions of a loop kept on disk (laws in use, package edits)


class LawKernel:
    """A numba function that calls the friction law; compiled per law by ``for_law``."""

    def __init__(self, py_func, options: dict):
        self.py_func = py_func
        self.options = options
        self.__name__ = py_func.__name__
        self.__doc__ = py_func.__doc__
        self._compiled = {}

    def __call__(self, *args, **kwargs):
        raise TypeError(f"{self.__name__} runs a friction law: call {self.__name__}.for_law(law)(...)")

    def for_law(self, law):
        """This function compiled with ``law``'s update (a numba dispatcher)."""
        compiled = self._compiled.get(law.fingerprint)
        if compiled is None:
            namespace = dict(self.py_func.__globals__)
            namespace["law_update"] = law.update
            namespace["law_energy"] = law.stored_energy
            f = self.py_func
            for name in f.__code__.co_names:  # the law kernels this one calls
                value = namespace.get(name)
                if isinstance(value, LawKernel) and value is not self:
                    namespace[name] = value.for_law(law)
            function = types.FunctionType(f.__code__, namespace, f.__name__, f.__defaults__,
                                          f.__closure__)
            function.__qualname__ = f"{f.__qualname__}__{law.fingerprint}"
            function.__module__ = f.__module__
            function.__doc__ = f.__doc__
            compiled = njit(**self.options)(function)
            self._compiled[law.fingerprint] = compiled
            if self.options.get("cache"):
                _prune(compiled, f"{Path(f.__code__.co_filename).stem}.{f.__qualname__}__")
        return compiled


def _prune(dispatcher, prefix: str) -> None:
    """Remove the compiled versions of a loop beyond the KEPT_VERSIONS most recent
    (best effort: another process may be removing or writing them too)."""
    try:
        directory = Path(dispatcher._cache._cache_path)  # numba's cache locator
    except AttributeError:
        return
    versions = {}
    try:
        for path in directory.glob(prefix + "*.nb[ic]"):
            fingerprint = path.name[len(prefix):].split("-", 1)[0]
            versions.setdefault(fingerprint, []).append((path.stat().st_mtime, path))
        newest = sorted(versions, key=lambda key: max(versions[key])[0], reverse=True)
        for fingerprint in newest[KEPT_VERSIONS:]:
            for _, path in versions[fingerprint]:
                path.unlink(missing_ok=True)
    except OSError:
        pass


def law_kernel(**options):
    """Decorator: like ``numba.njit(**options)``, for a function that calls ``law_update``."""
    return lambda py_func: LawKernel(py_func, options)
