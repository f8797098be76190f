"""What a friction law is: the contract every law, built in or a user's, fulfils.

A law is a Python module (a file or an importable module) that defines

    PARAMETERS      {name: Parameter}: the law's keys in the scene's [contact]
                    table, with defaults, units and valid ranges, in the order
                    compiled_parameters() hands them to ``update``; among them
                    mu and k_t (SHARED_PARAMETERS: SHARED_RULE says why)
    STATE_SIZE      the number of floats each contact node carries
    INITIAL_STATE   a node's state before any motion (STATE_SIZE floats)
    ORDER           the order in dt at which its update converges

    update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt)
        -> (F_x, F_y)
        One node over one step, the VFRIC analogue, compiled with numba
        (nopython; helpers it calls must be @numba.njit). Phase 1: the body
        end moves by the slip increment (body minus base); phase 2: the free
        end by (free_x, free_y) (eq 30). ``normal_force`` <= 0 means out of
        contact. ``area_share`` is the node's share of the contact area: the
        law shares its whole-contact stiffnesses out by it. ``state`` (its
        STATE_SIZE floats) is updated in place; ``params`` is the float array
        compiled_parameters() made. Returns the friction force F, which acts
        on the body as -F.

        A changing normal force: an FE node's N changes every step (the block
        rocks), the lumped body's never. Every step's force lies within
        bounds().max_friction_coefficient times *that step's* normal force,
        whatever the node held before: what it holds beyond a limit that
        dropped returns to the limit at once (Coulomb's inequality at every
        instant; the radial return of computational contact). N <= 0 releases
        the node: force 0, and back in contact it starts from rest. And the
        force goes to 0 with N while the state stays bounded: a node that
        opens passes through ever smaller N on its way to 0 (the lumped body
        lifting off), where the sliding length mu N / k_t vanishes, so no
        division by N and no update stable only while the slip a step is below
        the sliding length (the paper's explicit Dahl update is not: its state
        grows without bound there). The conformance suite
        (tests/test_law_contract.py) checks all three under a swinging, jumping
        and vanishing N. The asperity laws offer two other
        rules for comparison (asperity.py: normal_change).

    stored_energy(state, params, area_share) -> float
        The elastic energy the node's state holds (J), compiled; for the
        energy balance (fem.energy).

    bounds(p, dt) -> Bounds
        What the integrators need to know of the law at the step dt. ``p``, here
        and below, holds the parameter values by name and F_N, the contact's
        normal load, read either way: ``p.mu`` or ``p["mu"]`` (LawValues).

    steady_sliding_force(p, normal_force, v) -> float
        The friction force once sliding has settled at the constant slip rate v.

and optionally

    compiled_parameters(p) -> sequence of floats   (default: PARAMETERS' values in order;
                                                    a choice passes its index)
    deformation(states) -> (n, 2) array             the elastic deformation of each node's
                                                    state (n, STATE_SIZE), for ParaView
    check(p) -> None                                raises ValueError(name, message) for a
                                                    combination of values the law refuses

The loaded law (FrictionLaw) compiles ``update`` into every time loop that
uses it (specialize.py); ``fingerprint`` names the compiled code by the law's
source and the package's, so an edited law is never run from a stale cache.
An exception out of a user's law function is the law's: a LawError naming the
law file, its line and the function (law_fault), never a crash of vibrofric.
"""

import functools
import hashlib
import importlib
import importlib.util
import math
import sys
import traceback
import types
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numba import njit

FASTMATH = {"arcp", "contract"}
BUILT_IN = {"dahl": "vibrofric.friction_law.dahl", "lugre": "vibrofric.friction_law.lugre"}
PACKAGE = Path(__file__).resolve().parent.parent
REQUIRED = ("PARAMETERS", "STATE_SIZE", "INITIAL_STATE", "ORDER", "update", "stored_energy",
            "bounds", "steady_sliding_force")
# The parameters every law declares, whatever else it takes: every scene sets them in
# [contact] for whichever law runs (so ``--set contact.law=...`` switches the law of any
# scene), and the model reads its drive-force ratio and contact stiffness from them.
SHARED_PARAMETERS = ("mu", "k_t")
SHARED_RULE = ("every friction law declares the parameters mu, its friction coefficient "
               "(F_d0 = mu F_N, the steady sliding force F_dv is measured against), and k_t, "
               "the contact's tangential stiffness (N/m), which every scene sets in [contact]")


class LawError(ValueError):
    """A law that cannot be loaded or breaks the contract: one line; ``detail`` holds the
    full message behind it (numba's) where there is one."""

    def __init__(self, message: str, detail: str = ""):
        super().__init__(message)
        self.detail = detail


def where_in_law(err: BaseException, source) -> str:
    """``source, line N (its text)``: the law file and its innermost line in ``err``'s
    traceback (the file alone where no frame is the law's)."""
    path = str(source)
    where = path
    for frame in traceback.extract_tb(err.__traceback__):
        if frame.filename == path:
            where = f"{path}, line {frame.lineno}" + (f" ({frame.line.strip()})"
                                                      if frame.line else "")
    return where


def law_fault(err: BaseException, source, function: str) -> LawError:
    """An exception raised inside a user's law function as a LawError in one line:
    the law file and the line of it where the exception arose, the function, the
    exception, and that the law is at fault."""
    message = f"{type(err).__name__}: {err}" if str(err) else type(err).__name__
    return LawError(f"{where_in_law(err, source)}: the law's {function}() raised {message}; "
                    "an error in the law file, not in vibrofric: fix the law (the contract: "
                    "vibrofric.friction_law.contract)")


class ParameterError(ValueError):
    """A law parameter's value out of its declared range; ``name`` names it."""

    def __init__(self, name: str, message: str):
        super().__init__(message)
        self.name = name


@dataclass(frozen=True)
class Parameter:
    """One law parameter: its default, unit, valid range (or choices) and meaning.

    default  a number, a string (then ``choices`` lists the valid ones), or None
             for "derived by the law from the others" (e.g. LuGre's F_s = mu F_N)
    low, high, low_open  the valid range: low <= value <= high (low < value if low_open)
    """

    default: object
    unit: str = ""
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    choices: tuple = ()
    doc: str = ""

    def check(self, name: str, value):
        """The value as the law takes it (a float, or one of the choices); raises ParameterError."""
        if self.choices:
            if value not in self.choices:
                raise ParameterError(name, f"must be one of {', '.join(self.choices)}, got {value!r}")
            return value
        if value is None and self.default is None:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParameterError(name, f"expected a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise ParameterError(name, f"expected a finite number, got {value!r}")
        if value < self.low or (self.low_open and value == self.low) or value > self.high:
            low = "(" if self.low_open else "["
            raise ParameterError(name, f"must lie in {low}{self.low:g}, {self.high:g}], got {value:g}")
        return value


@dataclass(frozen=True)
class Bounds:
    """What the integrators need of a law, for the whole contact at a step dt.

    stiffness             N/m: the tangent dF/d(slip) at rest (the implicit matrix's
                          friction part, the reduction's linearized contact, the
                          preload's regularization)
    max_stiffness         N/m: the largest tangent (the explicit stable step)
    friction_coefficient  F / F_N in steady sliding (the sliding length F / stiffness)
    max_friction_coefficient  the largest |F| / F_N the law reaches (tipping,
                          divergence checks)
    departure             a bound of |dF/d(slip) - stiffness| / stiffness over one
                          step of dt (the implicit contact iteration's contraction)
    """

    stiffness: float
    max_stiffness: float
    friction_coefficient: float
    max_friction_coefficient: float
    departure: float

    def sliding_length(self, normal_force: float) -> float:
        """The slip that brings the law to sliding: F_c / stiffness (Dahl: s_c)."""
        return self.friction_coefficient * normal_force / self.stiffness


def _source_hash(paths, root: Path) -> str:
    """A hash of the files' names (relative to root) and contents."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


@functools.cache
def package_hash() -> str:
    """A hash of the package's sources: any edit makes every law's compiled loops anew."""
    return _source_hash(sorted(PACKAGE.rglob("*.py")), PACKAGE)


def is_law_file(name) -> bool:
    """Whether ``contact.law`` names a file (a .py, or a path) rather than a built-in or module."""
    return isinstance(name, str) and (name.endswith(".py") or "/" in name or "\\" in name)


class LawValues(types.SimpleNamespace):
    """``p``, what a law's Python functions take: its parameter values by name and F_N,
    the contact's normal load, read as attributes (``p.mu``) or items (``p["mu"]``)."""

    def __getitem__(self, name: str):
        try:
            return getattr(self, name)
        except AttributeError:
            raise KeyError(name) from None

    def __contains__(self, name: str) -> bool:
        return hasattr(self, name)


@dataclass(frozen=True, eq=False)
class FrictionLaw:
    """A loaded law: its module, its compiled per-node update, and its fingerprint."""

    name: str               # as the scene gives it: "dahl", a module name, or a file path
    module: types.ModuleType
    fingerprint: str        # hash of the law's source and the package's (compiled-code name)
    update: object = field(repr=False)          # numba dispatcher, inlined into the loops
    stored_energy: object = field(repr=False)
    checked_update: object = field(default=None, repr=False)  # a law file's update with bounds
                                                              # checks (law_check), else None

    def probe(self, contact_law: "ContactLaw", dt: float) -> None:
        """A law file's first steps at these parameter values, bounds-checked
        (law_check.probe_law); raises LawError. Nothing for a built-in law."""
        if self.checked_update is not None:
            from .law_check import probe_law
            probe_law(self.checked_update, contact_law, dt, self.name)

    @property
    def parameters(self) -> dict:
        return self.module.PARAMETERS

    @property
    def built_in(self) -> bool:
        return self.name in BUILT_IN

    def call(self, function: str, *args):
        """The module's ``function`` called on ``args``; an exception out of a user's law
        is raised as the law's (law_fault), one out of a built-in law as it is (a bug)."""
        try:
            return getattr(self.module, function)(*args)
        except (LawError, ParameterError):
            raise
        except Exception as err:
            if self.built_in:
                raise
            raise law_fault(err, self.module.__file__, function) from None

    @property
    def state_size(self) -> int:
        return self.module.STATE_SIZE

    def values(self, given: dict) -> dict:
        """Every parameter's value, ``given`` checked and the defaults filled in.

        Raises ParameterError naming an unknown or invalid parameter.
        """
        unknown = sorted(set(given) - set(self.parameters))
        if unknown:
            raise ParameterError(unknown[0], f"not a parameter of the friction law {self.name!r}; "
                                             f"its parameters: {', '.join(self.parameters)}")
        values = {name: parameter.check(name, given.get(name, parameter.default))
                  for name, parameter in self.parameters.items()}
        return values

    def check(self, p) -> None:
        """The law's own check of a combination of values (optional ``check(p)``)."""
        if hasattr(self.module, "check"):
            try:
                self.module.check(p)
            except ValueError as err:   # the law refuses these values (the contract)
                name, message = err.args if len(err.args) == 2 else ("law", str(err))
                raise ParameterError(name, message) from None
            except Exception as err:
                if self.built_in:
                    raise
                raise law_fault(err, self.module.__file__, "check") from None

    def compiled_parameters(self, p) -> np.ndarray:
        """The float array ``update`` takes (module.compiled_parameters, else the values in order)."""
        if hasattr(self.module, "compiled_parameters"):
            values = self.call("compiled_parameters", p)
        else:
            values = [parameter.choices.index(getattr(p, name)) if parameter.choices
                      else getattr(p, name) for name, parameter in self.parameters.items()]
        return np.array(values, dtype=np.float64)

    def initial_state(self, nodes: int) -> np.ndarray:
        """(nodes, STATE_SIZE): every node at rest."""
        return np.tile(np.asarray(self.module.INITIAL_STATE, dtype=np.float64), (nodes, 1))

    def deformation(self, states: np.ndarray) -> np.ndarray:
        """(n, 2) elastic deformation of each node's state (zeros if the law does not say)."""
        if hasattr(self.module, "deformation"):
            return np.asarray(self.call("deformation", states), dtype=np.float64)
        return np.zeros((states.shape[0], 2))


def _load_module(name: str):
    """The law's module and its source file: a built-in name, a .py path or a module name."""
    if name in BUILT_IN:
        module = importlib.import_module(BUILT_IN[name])
        return module, Path(module.__file__)
    if is_law_file(name):
        path = Path(name)
        if not path.is_file():
            raise LawError(f"no friction law file {path}")
        # A module named by the file's content (an edited file is loaded anew): the law's
        # compiled loops are cached by its fingerprint, the content's, and numba's cached
        # code imports the module by that name in any later process. Loaded from another
        # place, it is executed again from this one under the same name: numba finds a
        # function's cache by its module's file, and a copy served by the original's
        # module (a results directory's law file) failed to compile once the original
        # was gone ("no locator available for file").
        digest = hashlib.sha256(path.read_bytes()).hexdigest()[:12]
        module_name = f"vibrofric_law_{path.stem}_{digest}"
        loaded = sys.modules.get(module_name)
        if loaded is not None and Path(loaded.__file__).resolve() == path.resolve():
            return loaded, path
        spec = importlib.util.spec_from_file_location(module_name, path)
        if spec is None:   # Python loads only a source file it recognizes by its suffix
            raise LawError(f"friction law file {path}: not a Python file (name it .py)")
        module = importlib.util.module_from_spec(spec)
        sys.modules[module_name] = module
        def unload():   # the module of the other place, if any, as it was
            if loaded is None:
                del sys.modules[module_name]
            else:
                sys.modules[module_name] = loaded

        try:
            spec.loader.exec_module(module)
        except KeyboardInterrupt:
            unload()
            raise
        except BaseException as err:  # SystemExit too: a law's import never ends the run
            unload()
            raise LawError(f"{where_in_law(err, path)}: could not be loaded: "
                           f"{type(err).__name__}: {err}") from None
        return module, path
    try:
        module = importlib.import_module(name)
    except ImportError as err:
        raise LawError(f"{name!r} is neither a built-in law ({', '.join(BUILT_IN)}), a .py file "
                       f"nor an importable module ({err})") from None
    return module, Path(module.__file__)


def _check_contract(module, where: str) -> None:
    missing = [name for name in REQUIRED if not hasattr(module, name)]
    if missing:
        raise LawError(f"{where} is not a friction law: it lacks {', '.join(missing)} "
                       "(see vibrofric.friction_law.contract)")
    if not isinstance(module.PARAMETERS, dict) or not all(
            isinstance(p, Parameter) for p in module.PARAMETERS.values()):
        raise LawError(f"{where}: PARAMETERS must map names to friction_law.Parameter")
    lacking = [name for name in SHARED_PARAMETERS if name not in module.PARAMETERS]
    if lacking:
        raise LawError(f"{where}: PARAMETERS lacks {' and '.join(lacking)}: {SHARED_RULE}")
    if not isinstance(module.STATE_SIZE, int) or module.STATE_SIZE < 1:
        raise LawError(f"{where}: STATE_SIZE must be an integer >= 1")
    if len(module.INITIAL_STATE) != module.STATE_SIZE:
        raise LawError(f"{where}: INITIAL_STATE must hold STATE_SIZE = {module.STATE_SIZE} values")
    if not (isinstance(module.ORDER, (int, float)) and module.ORDER > 0):
        raise LawError(f"{where}: ORDER must be a positive number")


def _inlined(function):
    """The law's function compiled to be inlined into the time loops that call it."""
    py_func = getattr(function, "py_func", function)
    return njit(error_model="numpy", fastmath=FASTMATH, inline="always")(py_func)


_LOADED = {}


def load_law(name: str) -> FrictionLaw:
    """The friction law ``name``: a built-in, a .py file (relative to the current directory;
    the scene resolves one named in a scene file), or an importable module.

    A law file or module is compiled with numba here, before any other work, and its
    types checked (law_check.compile_law). Raises LawError for a law that cannot be
    found, breaks the contract or cannot be compiled.
    """
    module, source = _load_module(name)
    key = (module.__name__, source)
    if key not in _LOADED:
        where = str(source) if name not in BUILT_IN else name
        _check_contract(module, where)
        checked = None
        if name not in BUILT_IN:  # a user's law: compiled and type-checked now (law_check)
            from .law_check import compile_law
            checked = compile_law(module, where)
        law_file = source.resolve()
        digest = hashlib.sha256((package_hash() + _source_hash([law_file], law_file.parent)).encode())
        _LOADED[key] = FrictionLaw(name, module, digest.hexdigest()[:16],
                                   _inlined(module.update), _inlined(module.stored_energy),
                                   checked)
    return _LOADED[key]


@dataclass(frozen=True, eq=False)
class ContactLaw:
    """A law with its parameter values, for a contact of total normal load F_N."""

    law: FrictionLaw
    values: dict
    F_N: float

    @property
    def p(self) -> LawValues:
        """The values by name, and F_N: what the law's Python functions take."""
        return LawValues(**self.values, F_N=self.F_N)

    @property
    def params(self) -> np.ndarray:
        return self.law.compiled_parameters(self.p)

    def bounds(self, dt: float) -> Bounds:
        return self.law.call("bounds", self.p, dt)

    def steady_sliding_force(self, normal_force: float, v: float) -> float:
        return float(self.law.call("steady_sliding_force", self.p, normal_force, v))
