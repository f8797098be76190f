"""Time loops compiled for one friction law: the law's update linked in, cached on disk.

A time loop (the lumped steppers, the FE integrators) calls the law as the
global ``law_update`` (and ``law_energy`` for its stored energy). Written with
``@law_kernel(...)`` instead of ``@njit(...)``, a loop is compiled per law:
``loop.for_law(law)`` rebuilds the function with the law's compiled update in
its globals, and every other law kernel it calls rebuilt the same way, then
compiles it with numba, cached on disk under a name that carries
``law.fingerprint`` (the law's source and the package's). So the law is
compiled into the loop's machine code, a second run loads the compiled loop
from the cache, and an edited law or package compiles anew: no stale
compiled code is ever used. Of each loop the KEPT_VERSIONS most recent
compiled versions stay on disk: a built-in law's beside the package's sources
(numba's __pycache__), a user's law's in the user's cache directory
(law_cache.py).

The law's functions enter the loops as functions of their own (``_called``:
compiled once per law, linked into each loop, where LLVM inlines them or
not), not through numba's inlining (inline="always"), which types and
lowers the law afresh at every call site: with it the reduced FE loop took
131 s to compile with Dahl's law, without it 27 s, its results the same to
the bit and its speed within 2% (docs/first-answer.md).

A law kernel's machine code is self-contained (``self_contained_law_kernels``):
the functions it calls are linked into it as copies under names of its own, so
its bits are the same whether it was compiled in this process or loaded from
the cache, and whichever way its callees came. So the loops' parts can be law
kernels of their own, each compiled once per law and linked where it is called
(the implicit step's contact iteration: contact_solve.py), instead of inlined
by numba into one large function, which numba types afresh at every call site.

Compiling is announced, never hidden: ``loop.prepared(law, args, what)``
returns the loop compiled for ``law`` and the types of ``args`` (the call a
run is about to make), loaded from numba's cache when it is there; when it is
not, it says so on stderr first ("vibrofric: compiling the reduced FE loop
for maxwell_slip.py, first run only") and compiles, so that a caller can
start its clock (a progress bar's rate) after it. Processes that need the
same loop at once (a sweep's workers, MPI ranks, parallel tests) compile it
one at a time under a lock beside numba's cache files: the first one
compiles and writes the cache, the others load it. A cache entry that fails
to load (damaged, or written by an incompatible build) is dropped and the
loop compiled anew.

A user's law never seen before is first run through its pointer
(through_pointer.py: ``loop.through_pointer()``, the loops compiled once for
every law at set-up), its update alone compiled, while the loops specialized for
it are compiled after the run, in the background (specialize_later.py); its
next runs load those. The two give the same results or differ at rounding level
(docs/first-answer.md); a sweep compiles the specialized loops first
(``specialized_first``), so that every sweep runs the same code.
VIBROFRIC_SPECIALIZE=now compiles them at first use instead, as before.
"""

import functools
import hashlib
import os
import sys
import threading
import types
from contextlib import ExitStack, contextmanager
from pathlib import Path

from llvmlite.binding import Linkage
from numba import njit
from numba import types as numba_types

from ..disk_cache import locked
from . import through_pointer
from .contract import BUILT_IN, FASTMATH, LawError, package_hash
from .law_cache import cache_in_user_directory

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
        return self._compiled_with(law.fingerprint, lambda kernel: kernel.for_law(law),
                                   _called(law, "update"), _called(law, "stored_energy"),
                                   user_law=law.name not in BUILT_IN)

    def through_pointer(self):
        """This function compiled once for every law, calling the law through the
        pointer in through_pointer.py's slots (a numba dispatcher; see ``prepared``)."""
        return self._compiled_with(pointer_fingerprint(), LawKernel.through_pointer,
                                   through_pointer.law_update, through_pointer.law_energy)

    def _compiled_with(self, fingerprint: str, callees, update, energy, user_law=False):
        """This function with ``update`` and ``energy`` as its ``law_update`` and
        ``law_energy``, the law kernels it calls made by ``callees``, compiled by numba
        under a name carrying ``fingerprint``; cached under the user's cache directory
        where it is a user's law's (``user_law``), else beside the package's source."""
        compiled = self._compiled.get(fingerprint)
        if compiled is None:
            namespace = dict(self.py_func.__globals__)
            namespace["law_update"] = update
            namespace["law_energy"] = energy
            f = self.py_func
            for name in f.__code__.co_names:  # the law kernels this one calls
                value = namespace.get(name)
                if isinstance(value, LawKernel) and value is not self:
                    namespace[name] = callees(value)
            function = types.FunctionType(f.__code__, namespace, f.__name__, f.__defaults__,
                                          f.__closure__)
            function.__qualname__ = f"{f.__qualname__}__{fingerprint}"
            function.__module__ = f.__module__
            function.__doc__ = f.__doc__
            _LAW_FINGERPRINTS.add(fingerprint)
            compiled = njit(**self.options)(function)
            if self.options.get("cache") and user_law:
                cache_in_user_directory(compiled)   # not the package's __pycache__
            self._compiled[fingerprint] = compiled
            if self.options.get("cache"):
                _prune(compiled, f"{Path(f.__code__.co_filename).stem}.{f.__qualname__}__")
        return compiled

    def prepared(self, law, args, what: str, direct: bool = False):
        """This function compiled with ``law`` for ``args``' types, loaded or compiled now
        (announced: "compiling <what> for <law>, first run only"); see the module. For a
        user's law, an exception out of it is the law's (blamed_on_law).

        A user's law whose specialized function is neither in memory nor in numba's
        cache is run through the law's pointer instead (``through_pointer``, loaded
        from the cache: compiled at set-up), its update alone compiled now; the
        specialized function is compiled after the run, in the background
        (specialize_later.py), for the next runs. Once chosen for a function, law and
        types, the route is kept for the rest of the process.

        With ``direct``, the compiled code for ``args``' types itself, called without
        numba's dispatch, which types every argument again at each call to pick that
        code (for the FE steps' tuples of arrays, as long as a whole base cycle of the
        reduced step, which the shooting calls once a cycle: docs/periodic.md). Only
        for a caller that passes arguments of those same types at every call."""
        dispatcher = self.for_law(law)
        sig = signature(dispatcher, args)
        pointers = None
        if _forced_pointer[0]:
            pointers = law_pointers(law)
        elif law.name not in BUILT_IN and specialize_when() == "later":
            route = (self, law.fingerprint, sig)
            pointers = _THROUGH_POINTER.get(route)
            if pointers is None and will_compile(dispatcher, sig):
                pointers = _THROUGH_POINTER[route] = law_pointers(law)
                from .specialize_later import schedule
                schedule(self, law, sig)
        if pointers is not None:
            dispatcher = self.through_pointer()
            sig = ready(dispatcher, sig, f"{what}, for every law")
        else:
            ready(dispatcher, sig, f"{what} for {law_label(law)}")
        function = dispatcher.overloads[sig].entry_point if direct else dispatcher
        if pointers is not None:
            function = pointers.calling(function)
        return function if law.name in BUILT_IN else blamed_on_law(law, function)


_THROUGH_POINTER = {}   # (kernel, law's fingerprint, types) -> the law's LawPointers
_LAW_POINTERS = {}      # law's fingerprint -> its LawPointers
_forced_pointer = [False]


def specialize_when() -> str:
    """When a user's law's specialized loops are compiled (``VIBROFRIC_SPECIALIZE``):
    "later" (its first runs call it through a pointer while they compile in the
    background: the default) or "now" (at first use, before the run)."""
    when = os.environ.get("VIBROFRIC_SPECIALIZE", "later")
    if when not in ("later", "now"):
        raise ValueError(f"VIBROFRIC_SPECIALIZE must be \"later\" or \"now\", got {when!r}")
    return when


def specialized_first(function):
    """Decorator for a sweep: a user's law's specialized loops are compiled (or loaded)
    before its points run (VIBROFRIC_SPECIALIZE=now, in its process and its workers'),
    so that every point of every sweep runs the same code: the pointer's and the
    specialized loops' results may differ at rounding level (docs/first-answer.md)."""
    @functools.wraps(function)
    def run(*args, **kwargs):
        before = os.environ.get("VIBROFRIC_SPECIALIZE")
        os.environ["VIBROFRIC_SPECIALIZE"] = "now"
        try:
            return function(*args, **kwargs)
        finally:
            if before is None:
                del os.environ["VIBROFRIC_SPECIALIZE"]
            else:
                os.environ["VIBROFRIC_SPECIALIZE"] = before
    return run


@contextmanager
def pointer_route():
    """Run every law, built-in ones too, through its pointer (the loops compiled for
    every law: vibrofric.warm compiles them at set-up; tests compare the routes)."""
    _forced_pointer[0] = True
    try:
        yield
    finally:
        _forced_pointer[0] = False


def law_pointers(law) -> "through_pointer.LawPointers":
    """The law's update and stored energy compiled for the pointer's signature (loaded
    from numba's cache, or compiled now, announced) and their addresses."""
    pointers = _LAW_POINTERS.get(law.fingerprint)
    if pointers is None:
        if law.name not in BUILT_IN:
            announce(f"{law_label(law)}: its update compiled (when the scene was read), the "
                     "loops call it through a pointer on this first run; the loops of its own "
                     "are compiled after the run, in the background")
        update, energy = _called(law, "update"), _called(law, "stored_energy")
        ready(update, through_pointer.UPDATE.args, f"the update of {law_label(law)}")
        ready(energy, through_pointer.ENERGY.args, f"the stored energy of {law_label(law)}")
        pointers = _LAW_POINTERS[law.fingerprint] = through_pointer.LawPointers(update, energy)
    return pointers


def blamed_on_law(law, dispatcher):
    """``dispatcher`` (or its compiled code: LawKernel.prepared) with an exception
    raised in it turned into a LawError naming the law: a user's law runs
    bounds-checked, and the loops themselves raise nothing, so an IndexError or a
    ``raise`` there is the law's, on a state or an input its first steps (checked
    when it was loaded: law_check) did not reach, such as an FE node's area share
    below 1 or a count of calls."""
    def run(*args):
        try:
            return dispatcher(*args)
        except Exception as raised:   # through the law's pointer: LawRaised, from the law's
            err = raised.__cause__ if isinstance(raised, through_pointer.LawRaised) else raised
            if isinstance(err, IndexError):
                raise LawError(f"{law.name}: update indexed outside its state (STATE_SIZE = "
                               f"{law.state_size}) or its parameters during the run, past "
                               "the first steps checked when it was loaded") from None
            raise LawError(f"{law.name}: update raised {type(err).__name__}: {err} during the "
                           "run, past the first steps checked when it was loaded") from None
    return run


_CALLED = {}
_LAW_FINGERPRINTS = set()   # the laws whose functions are compiled self-contained


def _self_contained(optimize):
    """numba's CPUCodeLibrary._optimize_final_module, first giving a law kernel's linked-in
    functions names of its own (see ``self_contained_law_kernels``)."""
    def run(library):
        if library.name.rpartition("__")[2] in _LAW_FINGERPRINTS:
            functions = list(library._final_module.functions)
            own = sorted(f.name for f in functions
                         if not f.is_declaration and f.linkage == Linkage.external)
            suffix = hashlib.sha1("\n".join(own).encode()).hexdigest()[:16]
            for function in functions:
                if not function.is_declaration and function.linkage == Linkage.linkonce_odr:
                    function.name = f"{function.name}.in.{suffix}"
        return optimize(library)
    run.vibrofric = True
    return run


def self_contained_law_kernels():
    """Make every law kernel's machine code self-contained: the same bits whether the
    functions it calls were compiled in this process or loaded from numba's cache.

    numba links the functions a function calls into its LLVM module as "linkonce_odr"
    copies, optimized there, where LLVM inlines them or keeps them as calls. A call kept
    is resolved when the machine code is loaded, by the copy's name: to the callee's
    own, separately compiled code if that is already loaded in the process (it is when
    the caller was compiled in it: compiling the caller compiled or loaded the callee
    first), else to the caller's copy (a caller loaded from the cache). Under
    fastmath's "contract" the two may fuse multiplies and adds differently: a new
    law's implicit run differed by 1.5e-12 of F_d between its first run and the next
    (docs/first-answer.md). Renamed for the caller (a name no other compiled function
    has: its own functions' names hashed) before LLVM optimizes the module, a kernel's
    copies are always the ones it calls, and its code is the same whichever way its
    callees came. LLVM's inlining decisions are unchanged (the copies keep their
    linkage).
    """
    from numba.core.codegen import CPUCodeLibrary

    # A numba method of its own (numba 0.56 and 0.68 have it): where a numba release has
    # not, the loops run as compiled, and tests/test_specialize.py says the copies are
    # not renamed, rather than the package failing to load.
    optimize = getattr(CPUCodeLibrary, "_optimize_final_module", None)
    if optimize is not None and not getattr(optimize, "vibrofric", False):
        CPUCodeLibrary._optimize_final_module = _self_contained(optimize)


self_contained_law_kernels()


def _called(law, name: str):
    """The law's function ``name`` compiled as a function the loops call (see the module),
    with the options contract.py compiles it with, less the inlining. (forceinline is
    set so that it is not inherited from the kernel whose compile first types it:
    contact_solve._node_over_step's.)"""
    key = (law.fingerprint, name)
    if key not in _CALLED:
        function = getattr(law, name)
        options = {key: value for key, value in getattr(function, "targetoptions", {}).items()
                   if key in ("error_model", "fastmath", "boundscheck")}
        py_func = getattr(function, "py_func", function)
        _CALLED[key] = njit(cache=True, **{"error_model": "numpy", "fastmath": FASTMATH,
                                           "forceinline": False, **options})(py_func)
    return _CALLED[key]


def pointer_fingerprint() -> str:
    """The name of the loops compiled for every law: the package's sources (a loop's
    law kernels live in several files, which numba's cache, keyed by the loop's own
    file, would not see change)."""
    return "p" + package_hash()[:15]


def law_label(law) -> str:
    """The law as a user named it: a built-in's name, a law file's name, a module's name."""
    return Path(law.name).name if law.name.endswith(".py") else law.name


_announcing = [True]


@contextmanager
def unannounced():
    """Compile without a line per loop (the caller has said what it compiles: vibrofric.warm)."""
    _announcing[0] = False
    try:
        yield
    finally:
        _announcing[0] = True


def announce(text: str) -> None:
    """One line on stderr, clear of any progress bar (tqdm's write)."""
    if not _announcing[0]:
        return
    from tqdm import tqdm

    tqdm.write(f"vibrofric: {text}", file=sys.stderr)


def signature(dispatcher, args) -> tuple:
    """The numba argument types of a call with ``args`` (as the dispatcher types them)."""
    return tuple(dispatcher.typeof_pyval(value) for value in args)


def _as_signature(dispatcher, args) -> tuple:
    """``args``' numba types, or ``args`` itself if it holds numba types (a signature)."""
    if isinstance(args, tuple) and all(isinstance(value, numba_types.Type) for value in args):
        return args
    return signature(dispatcher, args)


def will_compile(dispatcher, args) -> bool:
    """Whether calling ``dispatcher`` with ``args`` (or their types) compiles: neither in
    memory nor in numba's cache index on disk (a cached entry may still fail to load:
    ``ready``)."""
    sig = _as_signature(dispatcher, args)
    if sig in dispatcher.overloads:
        return False
    cache = dispatcher._cache          # numba's FunctionCache (NullCache without cache=True)
    try:
        key = cache._index_key(sig, dispatcher.targetctx.codegen())
        return key not in cache._cache_file._load_index()
    except Exception:                  # no cache, or an index numba cannot read
        return True


@contextmanager
def _compile_lock(dispatcher):
    """An exclusive lock beside the function's numba cache files (none without a cache)."""
    with ExitStack() as stack:
        try:
            cache = dispatcher._cache
            stack.enter_context(locked(Path(cache._cache_path)
                                       / f"{cache._cache_file._index_name}.lock"))
        except (AttributeError, OSError):   # numba's NullCache, or no lock to be had there
            pass
        yield


def ready(dispatcher, args, what: str) -> tuple:
    """Make ``dispatcher``'s code for ``args``' types (or for ``args``, numba types)
    available in this process: from memory, from numba's cache, or compiled once under
    the lock, announced. Returns those types (signature), for a caller that needs them
    too: typing the FE steps' tuples of arrays is not free."""
    sig = _as_signature(dispatcher, args)
    if sig in dispatcher.overloads:
        return sig
    if will_compile(dispatcher, sig):
        announce(f"compiling {what}, first run only")
    with _compile_lock(dispatcher):
        try:
            _compile_interruptibly(dispatcher, sig)  # numba loads it from its cache if
                                                     # another process wrote it
        except Exception:
            # A damaged or foreign cache entry: drop this function's index and compile
            # afresh; an error of the code itself comes again and is raised.
            try:
                dispatcher._cache.flush()
            except Exception:
                pass
            _compile_interruptibly(dispatcher, sig)
    return sig


def _compile_interruptibly(dispatcher, sig) -> None:
    """``dispatcher.compile(sig)`` in a helper thread while this one waits for it.

    numba compiles largely in LLVM's C code, calling back into Python through
    llvmlite's ctypes callbacks, which swallow an exception raised in them: a
    KeyboardInterrupt that Ctrl-C or SIGTERM raised there (parallel.interruptible)
    was lost, and a new law's loops compiled on for tens of seconds, after which
    the run went on. Signal handlers run in the main thread only, so while it
    waits here the signal's KeyboardInterrupt is raised here at once and the run
    ends through its clean-ups; the compile is abandoned (a daemon thread, gone
    with the process).
    """
    if threading.current_thread() is not threading.main_thread():
        dispatcher.compile(sig)
        return
    failure = []

    def compile_it():
        try:
            dispatcher.compile(sig)
        except BaseException as err:  # handed to the waiting thread
            failure.append(err)

    worker = threading.Thread(target=compile_it, name=f"compile {dispatcher.__name__}",
                              daemon=True)
    worker.start()
    while worker.is_alive():
        worker.join(0.05)
    if failure:
        raise failure[0]


def _prune(dispatcher, prefix: str) -> None:
    """Remove the compiled versions of a loop beyond the KEPT_VERSIONS most recent
    (best effort: another process may be removing or writing them too)."""
    try:
        directory = Path(dispatcher._cache._cache_path)  # numba's cache locator
    except AttributeError:
        return
    versions = {}
    try:
        for path in directory.glob(prefix + "*.nb[ic]*"):  # with the .nbi.lock files
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
