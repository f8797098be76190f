"""A user's friction law checked when it is loaded, before any mesh or FE work.

Three checks, each ending in one LawError line that names the law file, the
function and what is wrong (numba's own message, without its colours, kept in
``LawError.detail`` for ``--verbose``):

1. ``compile_law``: ``update`` and ``stored_energy`` are functions of the
   contract's arguments, and numba compiles them for the types the time loops
   pass (floats, the node's state and the parameters as 1D float arrays),
   with bounds checking on; ``update`` returns two numbers (F_x, F_y). A law
   numba cannot compile (a module-level dict, a helper without ``@njit``)
   fails here instead of deep inside a time loop.
2. ``probe_law``: with the scene's parameter values, the compiled update runs
   a short slip history (loading, a circle, the free end moving, the normal
   force dropping to 0 and coming back), from INITIAL_STATE: an exception it
   raises, an index outside its state or parameters, or a force that is not
   finite fails here, before the fast loops (which run without bounds checks)
   would return nonsense or crash on it.

The built-in laws are trusted (and tested); only law files and modules are checked.
"""

import inspect
import math
import re

import numpy as np
from numba import njit, types

from .contract import FASTMATH, LawError

ARGUMENTS = {"update": 9, "stored_energy": 3}
_STATE = types.Array(types.float64, 1, "C")
SIGNATURES = {
    "update": (types.float64,) * 6 + (_STATE, _STATE, types.float64),
    "stored_energy": (_STATE, _STATE, types.float64),
}
_ANSI = re.compile(r"\x1b\[[0-9;]*m")
_LINE = re.compile(r'File "([^"]+)", line (\d+)')
PROBE_STEPS = 48


def _plain(text: str) -> str:
    return _ANSI.sub("", text)


def _reason(message: str) -> str:
    """The line of numba's message that says what is wrong, and where (line N)."""
    lines = [line.strip() for line in _plain(message).splitlines()]
    skip = ("Failed in nopython mode", "During:", "File ", "<source", "Enable logging",
            "This error may have been", "^", "- Resolution failure", "No implementation of")
    reason = next((line for line in lines if line and not line.startswith(skip)),
                  lines[0] if lines else "no message")
    where = _LINE.findall(message)
    if where:
        reason += f" (line {where[0][1]})"
    if "Untyped global name" in reason and "function" in reason:
        reason += "; a helper it calls must be decorated with @numba.njit"
    return reason


def compile_law(module, where: str) -> object:
    """The law's ``update`` compiled for the loops' types with bounds checks (a numba
    dispatcher, for probe_law); raises LawError naming what cannot be compiled."""
    for name, count in ARGUMENTS.items():
        function = getattr(module, name)
        function = getattr(function, "py_func", function)
        if not inspect.isfunction(function):
            raise LawError(f"{where}: {name} must be a function, got {type(function).__name__} "
                           f"{function!r:.40}")
        given = len(inspect.signature(function).parameters)
        if given != count:
            raise LawError(f"{where}: {name} must take {count} arguments (see "
                           f"vibrofric.friction_law.contract), it takes {given}")
    compiled = {}
    for name, signature in SIGNATURES.items():
        function = getattr(module, name)
        function = getattr(function, "py_func", function)
        try:
            compiled[name] = _compiled(function, signature)
        except Exception as err:  # numba's TypingError, LoweringError, UnsupportedError...
            raise LawError(f"{where}: numba cannot compile {name}: {_reason(str(err))}",
                           detail=_plain(str(err))) from None
    returned = compiled["update"].nopython_signatures[0].return_type
    if not (isinstance(returned, types.BaseTuple) and len(returned) == 2
            and all(isinstance(t, (types.Float, types.Integer)) for t in returned)):
        raise LawError(f"{where}: update must return two numbers (F_x, F_y), it returns {returned}")
    return compiled["update"]


def _compiled(function, signature):
    """``function`` compiled by numba for ``signature`` with bounds checks, cached beside
    the law's file. A law file's module is named by the file's content
    (contract._load_module); an entry numba cached there under another module name (an
    earlier naming) cannot be loaded ("No module named 'vibrofric_law_..."), so the
    function's cache index is emptied and the function compiled anew."""
    dispatcher = njit(error_model="numpy", fastmath=FASTMATH, boundscheck=True,
                      cache=True)(function)
    try:
        dispatcher.compile(signature)
    except ModuleNotFoundError as err:
        if not (err.name or "").startswith("vibrofric_law_"):
            raise
        dispatcher._cache.flush()       # numba's FunctionCache: an empty index
        dispatcher.compile(signature)
    dispatcher.disable_compile()        # as njit(signature) leaves it
    return dispatcher


def probe_history(scale: float):
    """(slip, free, normal) over PROBE_STEPS steps: loading in X, a circle of radius
    2 scale, the free end moving in Y, the normal force at 0 for one step and back."""
    n = PROBE_STEPS
    slip = np.zeros((n, 2))
    free = np.zeros((n, 2))
    normal = np.ones(n)
    slip[:8, 0] = 0.3 * scale
    angles = np.linspace(0.0, 2.0 * math.pi, 25)
    circle = 2.0 * scale * np.column_stack([np.cos(angles), np.sin(angles)])
    slip[8:32] = np.diff(circle, axis=0)
    free[32:40, 1] = 0.4 * scale
    normal[40:44] = (0.5, 0.1, 0.0, 1.0)
    slip[40:, 1] = -0.2 * scale
    return slip, free, normal


def probe_law(update, contact_law, dt: float, where: str) -> None:
    """Run the bounds-checked ``update`` over probe_history on one node (area share 1) at
    the contact's normal load; raises LawError for an exception, an index out of bounds
    or a force that is not finite."""
    law = contact_law.law
    params = contact_law.params
    state = law.initial_state(1)[0]
    F_N = contact_law.F_N
    try:
        scale = contact_law.bounds(dt).sliding_length(F_N)
    except LawError:   # raised inside the law's bounds(): named by its file and line
        raise
    except Exception as err:
        raise LawError(f"{where}: bounds() failed: {type(err).__name__}: {err}") from None
    if not (math.isfinite(scale) and scale > 0.0):
        scale = 1e-7
    slip, free, normal = probe_history(scale)
    for step in range(PROBE_STEPS):
        try:
            force = update(slip[step, 0], slip[step, 1], free[step, 0], free[step, 1],
                           normal[step] * F_N, 1.0, state, params, dt)
        except IndexError:
            raise LawError(f"{where}: update indexes outside its state (STATE_SIZE = "
                           f"{law.state_size}) or its parameters ({params.size} values)") from None
        except Exception as err:
            raise LawError(f"{where}: update raised {type(err).__name__}: {err}") from None
        if not all(math.isfinite(value) for value in force):
            raise LawError(f"{where}: update returned a force that is not finite, {force}, at "
                           f"a slip of {abs(slip[step]).max() / scale:.2g} sliding lengths")
