"""Where numba keeps the code compiled for a user's friction law: the user's cache directory.

numba caches a function's machine code beside its source (``__pycache__``, its
in-tree locator). The time loops compiled for a law (specialize.LawKernel.for_law:
the package's loops with the law's update linked in) have the package's sources,
so a user's law would have its compiled loops written into the installed
package's ``__pycache__``: a directory the user may not be able to write
(numba then falls back to ~/.cache itself, per source file), and one that a
reinstall or ``make clean-cache`` does not treat as the user's. For a user's law
they go to ``disk_cache.cache_root()/numba`` instead (``$VIBROFRIC_CACHE/numba``,
else ``$XDG_CACHE_HOME/vibrofric/numba``, else ``~/.cache/vibrofric/numba``), in
the subdirectory numba's own NUMBA_CACHE_DIR locator would give the source file.
The built-in laws' loops stay in the package's ``__pycache__``, where ``make
setup`` compiles them (vibrofric warm). The law's own functions (its update, as
specialize._called compiles it for the loops) stay beside the law's file, which
is the user's: moved here too, a law that fails only after many calls
(tests/test_law_contract.py, "indexes-outside-after-many-calls") ran on without
its bounds check's IndexError, which was not looked into. A user who sets
NUMBA_CACHE_DIR keeps numba's own choice for everything.
"""

import os

from ..disk_cache import cache_root


def numba_cache_dir():
    """The directory under which a user's law's compiled code is cached."""
    return cache_root() / "numba"


def cache_in_user_directory(dispatcher) -> None:
    """Point ``dispatcher`` (numba, compiled with cache=True, nothing compiled yet) to a
    cache under numba_cache_dir(); left as numba made it where NUMBA_CACHE_DIR is set
    or where numba's caching machinery is not what this expects."""
    from numba.core import config

    if config.CACHE_DIR:
        return
    from numba.core import caching

    # numba 0.56 (Debian) names it with a leading underscore, 0.68 without
    user_locator = (getattr(caching, "UserProvidedCacheLocator", None)
                    or getattr(caching, "_UserProvidedCacheLocator", None))
    if user_locator is None:
        return
    CompileResultCacheImpl, FunctionCache = caching.CompileResultCacheImpl, caching.FunctionCache

    root = str(numba_cache_dir())

    class Locator(user_locator):
        """numba's NUMBA_CACHE_DIR locator, at ``root``."""

        def __init__(self, py_func, py_file):
            super().__init__(py_func, py_file)
            self._cache_path = os.path.join(root, self.get_suitable_cache_subpath(py_file))

        @classmethod
        def from_function(cls, py_func, py_file):
            if not os.path.exists(py_file):
                return None
            locator = cls(py_func, py_file)
            try:
                locator.ensure_cache_path()
            except OSError:
                return None
            return locator

    class Impl(CompileResultCacheImpl):
        _locator_classes = [Locator]

    class Cache(FunctionCache):
        _impl_class = Impl

    try:
        dispatcher._cache = Cache(dispatcher.py_func)
    except RuntimeError:   # no locator: the directory cannot be made; numba's own stays
        pass
