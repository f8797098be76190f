"""Scenes: the physics of one study case plus the numerics that run it.

A scene is a TOML file with the sections of docs/scenes.md. Every key has a
default (the paper's longitudinal case, docs/model.md section 4), so a file
holds only what differs; ``--set section.key=value`` overrides any key. Every
value is checked before any work: a bad one raises ``SceneError`` naming it.
"""

import dataclasses
import difflib
import functools
import math
import tomllib
import typing
from dataclasses import dataclass, field, fields
from pathlib import Path

import tomli_w

from .core import errors
from .friction_law import ContactLaw, LawError, ParameterError, load_law
from .friction_law.contract import BUILT_IN, is_law_file
from .meshes import level_counts
from .sense import nonsense


class SceneError(ValueError):
    """A scene value that cannot be run; the message names the key. ``detail``: a longer
    explanation behind the one line, where there is one (numba's message for a law)."""

    def __init__(self, key: str, message: str, detail: str = ""):
        super().__init__(f"{key}: {message}")
        self.key = key
        self.detail = detail


def law_refused(err: LawError) -> SceneError:
    """A friction law's failure as the scene's: under contact.law, numba's message kept."""
    return SceneError("contact.law", str(err), getattr(err, "detail", ""))


# The scene key a user changes when the model refuses a scene (core.errors):
# the numerics say what is wrong in the model's terms, the scene names the key.
REFUSAL_KEYS = {
    errors.StepTooLong: "time.dt",
    errors.NormalLoadTooSmall: "contact.F_N",
    errors.DriveTipsBlock: "drive.attach",
    errors.NoEnergyBalance: "fem.energy",
    errors.ReductionFailed: "fem.cutoff",
}


def refused(refusal: errors.Refusal) -> SceneError:
    """The model's refusal as a SceneError naming the key to change."""
    return SceneError(REFUSAL_KEYS[type(refusal)], str(refusal))


@dataclass(frozen=True)
class Body:
    mass: float = 0.5                      # kg
    size: tuple = (0.03, 0.04, 0.053)      # m: X (sliding), Y, Z (height)
    E: float = 209e9                       # Pa
    nu: float = 0.3
    density: typing.Optional[float] = None  # kg/m^3; default mass / volume
    gravity: float = 9.81                  # m/s^2, acting in -Z


@dataclass(frozen=True)
class Contact:
    """The contact: its friction law and normal load, and the law's parameters.

    The law's parameters come from two places in [contact]:

        [contact]            keys every law of the scene shares (k_t, mu): each must be a
                             parameter of the chosen law
        [contact.<law>]      keys for one law only (``law_key``: dahl, lugre, or a law
                             file's stem), applied only while that law is chosen, over
                             [contact]'s value of the same key

    so ``--set contact.law=...`` switches the law of any scene: the other laws' tables
    stay unapplied, and a typo is refused either way. Each parameter is readable as
    ``contact.<name>`` (friction_law/contract.py).
    """

    law: str = "dahl"                      # "dahl" | "lugre" | a law file (.py; relative to the
                                           # scene file) | an importable module
    F_N: float = 55.0                      # N, total normal reaction
    eta_y: float = 0.71                    # transverse vibration transfer coefficient (eq 30)
    parameters: dict = field(default_factory=dict)  # [contact]'s law parameters
    tables: dict = field(default_factory=dict)      # {law_key: {parameter: value}}

    @property
    def given(self) -> dict:
        """The parameters the scene sets for its chosen law: [contact]'s and its own table's."""
        return {**self.parameters, **self.tables.get(law_key(self.law), {})}

    @property
    def law_values(self) -> dict:
        """Every parameter of the law: those the scene sets, the law's defaults for the rest."""
        return load_law(self.law).values(self.given)

    def __getattr__(self, name):
        if name.startswith("__") or "parameters" not in self.__dict__:
            raise AttributeError(name)
        values = self.law_values
        if name in values:
            return values[name]
        raise AttributeError(f"the contact has no {name!r}: not a parameter of its law")


def law_key(name: str) -> str:
    """The name of a law's own table [contact.<key>]: a built-in's name, a law file's
    stem, an importable module's last part."""
    if is_law_file(name):
        return Path(name).stem
    return name.rpartition(".")[2]


CONTACT_KEYS = ("law", "F_N", "eta_y")     # the model's keys in [contact]; the rest are the law's


@dataclass(frozen=True)
class Drive:
    k_d: float = 96068.0                   # N/m
    v_d: float = 5e-4                      # m/s
    attach: str = "contact-plane"          # "contact-plane" | "front-face" (FE only)
    mode: str = "spring"                   # "spring" | "velocity"

    @property
    def prescribed(self) -> bool:
        """mode "velocity": the attachment moves at exactly v_d, no spring."""
        return self.mode == "velocity"


@dataclass(frozen=True)
class Vibration:
    f: float = 4000.0                      # Hz
    k_v: float = 6.0                       # v_a / v_d; 0 means no vibration
    theta_deg: float = 0.0                 # angle of the vibration axis to X
    t_on: float = 0.14                     # s


@dataclass(frozen=True)
class Time:
    T: float = 1.0                         # s, simulated time
    dt: float = 1e-6                       # s
    average_cycles: int = 0                # vibration cycles at the end averaged into F_dv;
                                           # 0: those nearest one drive-system period
    series_dt: float = 1e-5                # s, sampling of the written time series
    steady_tolerance: float = 0.0          # FE: stop once the window-averaged drive force changes
                                           # by at most this fraction over steady_cycles cycles;
                                           # 0: run to T (fem/steady.py)
    steady_cycles: int = 0                 # vibration cycles the settled average must hold;
                                           # 0: those of the averaging window
    settle_tolerance: float = 0.005        # a result is "settled" when its drive-force mean moved
                                           # by at most this fraction between the last two
                                           # averaging windows (analytic/summary.py)
    method: str = "transient"              # analytic: "transient" (step through T), "periodic"
                                           # (the steady cycle by shooting, analytic/periodic.py;
                                           # stepping where it fails) or "auto" (the same)


@dataclass(frozen=True)
class Fem:
    mesh: str = "coarse"                   # refinement level, see vibrofric.meshes
    integrator: str = "explicit"           # "explicit" | "implicit" | "reduced" | "auto"
                                           # (fem/integrators.py)
    penalty: typing.Optional[float] = None  # N/m for the whole contact face; default 10 E A / L_z
    output_every: int = 2000               # steps between ParaView frames; 0: none
    damping: float = 0.0                   # stiffness-proportional damping beta, s; 0: 6% at the top mode
    rho_infinity: float = 0.9              # implicit, reduced: generalized-alpha's spectral radius at
                                           # infinite frequency; 1 = trapezoidal rule (fem/implicit.py)
    cutoff: float = 12.0                   # reduced: keep the block's fixed-interface modes below
                                           # cutoff * vibration.f (fem/reduction.py)
    accuracy: float = 0.01                 # auto: the relative error of F_dv / F_d0 it may trade
                                           # for speed (fem/integrators.py)
    energy: bool = False                   # implicit, reduced: record the energy balance
                                           # (fem/energy.py)


SECTIONS = {"body": Body, "contact": Contact, "drive": Drive,
            "vibration": Vibration, "time": Time, "fem": Fem}

CHOICES = {
    "drive.attach": ("contact-plane", "front-face"),
    "drive.mode": ("spring", "velocity"),
    "fem.integrator": ("explicit", "implicit", "reduced", "auto"),
    "time.method": ("transient", "periodic", "auto"),
}


@dataclass(frozen=True)
class Scene:
    name: str = "scene"
    body: Body = field(default_factory=Body)
    contact: Contact = field(default_factory=Contact)
    drive: Drive = field(default_factory=Drive)
    vibration: Vibration = field(default_factory=Vibration)
    time: Time = field(default_factory=Time)
    fem: Fem = field(default_factory=Fem)

    # Derived quantities (docs/model.md section 1).
    @functools.cached_property
    def friction(self) -> ContactLaw:
        """The contact's friction law with its parameter values (friction_law.ContactLaw)."""
        c = self.contact
        law = load_law(c.law)
        return ContactLaw(law, law.values(c.given), c.F_N)

    @property
    def law_bounds(self):
        """What the integrators need of the law at time.dt (friction_law.Bounds)."""
        return self.friction.bounds(self.time.dt)

    @property
    def vibrated(self) -> bool:
        return self.vibration.k_v > 0.0

    @property
    def omega(self) -> float:
        return 2.0 * math.pi * self.vibration.f

    @property
    def v_a(self) -> float:
        """Velocity amplitude of the base, k_v v_d (eq 27)."""
        return self.vibration.k_v * self.drive.v_d

    @property
    def u0(self) -> float:
        """Displacement amplitude of the base, v_a / w (eq 27)."""
        return self.v_a / self.omega

    @property
    def F_c(self) -> float:
        """The steady sliding force of the law (Dahl: the Coulomb force mu F_N, eq 3)."""
        return self.law_bounds.friction_coefficient * self.contact.F_N

    @property
    def mu_max(self) -> float:
        """The largest friction coefficient the law reaches (LuGre: max(mu, F_s / F_N))."""
        return self.law_bounds.max_friction_coefficient

    @property
    def drive_period(self) -> float:
        """Period of the body on the drive spring, 2 pi sqrt(m / k_d)."""
        return 2.0 * math.pi * math.sqrt(self.body.mass / self.drive.k_d)

    @property
    def averaged_cycles(self) -> int:
        """Whole vibration cycles averaged into F_dv (eqs 40-41).

        By default those nearest one period of the drive system: the undamped
        body-on-spring oscillation left from breakaway then averages out too.
        A prescribed-velocity body has no such oscillation: 10 cycles.
        """
        if self.time.average_cycles:
            return self.time.average_cycles
        if self.drive.prescribed:
            return 10
        return max(1, round(self.drive_period * self.vibration.f))

    @property
    def steps(self) -> int:
        return int(round(self.time.T / self.time.dt))

    def get(self, key: str):
        section, name = _split_key(key)
        if "." in name:  # contact.<law>.<parameter>: that law's table
            law, name = name.split(".")
            return self.contact.tables.get(law, {}).get(name)
        return getattr(getattr(self, section), name)

    def with_values(self, values: dict) -> "Scene":
        """A copy with ``{"section.key": value}`` set and checked."""
        raw = to_dict(self)
        for key, value in values.items():
            _assign(raw, key, value)
        return from_dict(raw, self.name)

    def with_law(self, law: str, parameters: dict | None = None) -> "Scene":
        """A copy with another friction law and ``parameters`` for it in its own table;
        [contact]'s shared keys stay (each must be a parameter of the new law)."""
        raw = to_dict(self)
        raw["contact"]["law"] = law
        if parameters:
            raw["contact"][law_key(law)] = {**raw["contact"].get(law_key(law), {}), **parameters}
        return from_dict(raw, self.name)


def _split_key(key: str):
    """(section, name) of a scene key; a [contact] key other than CONTACT_KEYS is a law
    parameter (``contact.<name>``, or ``contact.<law>.<name>`` in a law's own table),
    checked against the law when the scene is built (_contact)."""
    section, _, name = key.partition(".")
    if section not in SECTIONS:
        raise SceneError(key, f"unknown section [{section}]; known: {', '.join(SECTIONS)}")
    if section == "contact" and all(part.isidentifier() for part in name.split(".")) \
            and name.count(".") <= 1 and name not in ("parameters", "tables"):
        return section, name
    if name not in {f.name for f in fields(SECTIONS[section])}:
        known = ", ".join(f.name for f in fields(SECTIONS[section]) if f.name != "tables")
        raise SceneError(key, f"unknown key in [{section}]; known: {known}")
    return section, name


def _assign(raw: dict, key: str, value) -> None:
    """Set ``section.key`` (or ``contact.<law>.<key>``) in the nested ``raw``. A law
    parameter that the chosen law's own table holds is set there: ``contact.update``
    changes the update of the law that runs."""
    section, name = _split_key(key)
    table = raw.setdefault(section, {})
    law, _, name = name.rpartition(".")
    if section == "contact" and not law and name not in CONTACT_KEYS:
        chosen = law_key(table.get("law", Contact.law))
        if name in (table.get(chosen) if isinstance(table.get(chosen), dict) else ()):
            law = chosen
    if law:
        table = table.setdefault(law, {})
        if not isinstance(table, dict):
            raise SceneError(key, f"contact.{law} is a value, not a law's table")
    table[name] = value


def _check_type(key: str, value, annotation):
    """Coerce a TOML value to the field's type, or refuse it."""
    optional = typing.get_origin(annotation) is typing.Union
    base = typing.get_args(annotation)[0] if optional else annotation
    if base is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SceneError(key, f"expected a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise SceneError(key, f"expected a finite number, got {value!r}")
        return value
    if base is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise SceneError(key, f"expected an integer, got {value!r}")
        return value
    if base is bool:
        if not isinstance(value, bool):
            raise SceneError(key, f"expected true or false, got {value!r}")
        return value
    if base is str:
        if not isinstance(value, str):
            raise SceneError(key, f"expected a string, got {value!r}")
        return value
    if base is tuple:
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise SceneError(key, f"expected a list of 3 numbers, got {value!r}")
        return tuple(_check_type(key, v, float) for v in value)
    raise TypeError(f"no type check for {annotation}")


def from_dict(raw: dict, name: str = "scene") -> Scene:
    """Build and validate a scene from nested ``{section: {key: value}}``."""
    sections = {}
    for section, values in raw.items():
        if section not in SECTIONS:
            raise SceneError(section, f"unknown section [{section}]; known: {', '.join(SECTIONS)}")
        if not isinstance(values, dict):
            raise SceneError(section, "expected a table of keys")
        if section == "contact":
            sections[section] = _contact(values)
            continue
        hints = typing.get_type_hints(SECTIONS[section])
        checked = {}
        for key, value in values.items():
            section_, key_ = _split_key(f"{section}.{key}")
            checked[key_] = _check_type(f"{section}.{key}", value, hints[key_])
        sections[section] = SECTIONS[section](**checked)
    scene = Scene(name=name, **sections)
    validate(scene)
    return scene


def _contact(values: dict) -> Contact:
    """[contact]: the model's keys, then the law's parameters checked against its declaration:
    [contact]'s shared keys and the chosen law's table against the chosen law, every
    built-in law's table against that law (a typo is refused whichever law runs)."""
    hints = typing.get_type_hints(Contact)
    own = {key: _check_type(f"contact.{key}", values[key], hints[key])
           for key in CONTACT_KEYS if key in values}
    law_name = own.get("law", Contact.law)
    law = _loaded(law_name)
    chosen = law_key(law_name)
    tables = {key: value for key, value in values.items() if isinstance(value, dict)}
    shared = {key: value for key, value in values.items()
              if key not in CONTACT_KEYS and key not in tables}
    for name, table in tables.items():
        _check_table(name, table, chosen)
    own_table = tables.get(chosen, {})
    try:
        shared_values = law.values(shared)
        checked = law.values({**shared, **own_table})
        law.check(ContactLaw(law, checked, own.get("F_N", Contact.F_N)).p)
    except ParameterError as err:
        table = f"{chosen}." if err.name in own_table else ""
        raise SceneError(f"contact.{table}{err.name}", str(err)) from None
    stored = {name: {key: _as_law_value(value) for key, value in table.items()}
              for name, table in tables.items()}
    if own_table:
        stored[chosen] = {key: checked[key] for key in own_table}
    return Contact(**own, parameters={key: shared_values[key] for key in shared}, tables=stored)


def _as_law_value(value):
    """A law parameter not checked yet (another law's table): a number as a float."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    return value


def _loaded(name: str):
    try:
        return load_law(name)
    except LawError as err:
        raise law_refused(err) from None


def _check_table(name: str, table: dict, chosen: str) -> None:
    """A law's own table: a built-in law's checked against it; another law's (a law file
    not chosen now) checked when that law runs; a likely misspelling refused."""
    for key in table:
        if isinstance(table[key], dict):
            raise SceneError(f"contact.{name}.{key}", "a law's table holds values, not tables")
    if name in BUILT_IN and name != chosen:
        try:
            load_law(name).values(table)
        except ParameterError as err:
            raise SceneError(f"contact.{name}.{err.name}", str(err)) from None
        return
    if name == chosen or name in BUILT_IN:
        return
    close = difflib.get_close_matches(name, [*BUILT_IN, chosen], n=1, cutoff=0.75)
    if close:
        raise SceneError(f"contact.{name}", f"no friction law {name!r} (did you mean "
                                            f"[contact.{close[0]}]?)")


def _law_path(value, base: Path):
    """A law file named relative to ``base`` as an absolute path; other values as they are."""
    if is_law_file(value):
        path = Path(value).expanduser()
        return str(path if path.is_absolute() else (base / path).resolve())
    return value


def parse_value(text: str):
    """A ``--set`` value: TOML syntax (``2``, ``1e-6``, ``[1, 2, 3]``, ``"dahl"``), else a bare string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_assignment(text: str):
    """``section.key=value`` -> (key, value)."""
    key, sep, value = text.partition("=")
    if not sep:
        raise SceneError(text, "expected section.key=value")
    if "\n" in text or "\r" in text:
        raise SceneError(key.strip(), f"{text!r} holds a line break: give one section.key=value "
                                      "per --set")
    key = key.strip()
    _split_key(key)
    return key, parse_value(value.strip())


def _read_scene_text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(str(path), "no such scene file") from None
    except IsADirectoryError:
        raise SceneError(str(path), "is a directory, not a scene file") from None
    except UnicodeDecodeError:
        raise SceneError(str(path), "is not a text file (not UTF-8): a scene is TOML") from None
    except OSError as err:
        raise SceneError(str(path), f"cannot be read: {err.strerror}") from None


def load(path, overrides=()) -> Scene:
    """Read a scene file and apply ``section.key=value`` overrides."""
    path = Path(path)
    text = _read_scene_text(path)
    if not text.strip():
        raise SceneError(str(path), "is empty: a scene holds the keys that differ from the "
                                    "defaults (a comment line alone runs the defaults)")
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SceneError(str(path), f"not valid TOML: {err}") from None
    for section, values in raw.items():
        if not isinstance(values, dict):
            raise SceneError(section, f"expected a table [{section}] of keys, got {values!r}")
    if "law" in raw.get("contact", {}):  # a law file is named relative to the scene file
        raw["contact"]["law"] = _law_path(raw["contact"]["law"], path.resolve().parent)
    for text in overrides:
        key, value = parse_assignment(text)
        # ... and on the command line, relative to the current directory
        _assign(raw, key, _law_path(value, Path.cwd()) if key == "contact.law" else value)
    return from_dict(raw, path.stem)


def check_key(key: str) -> None:
    """Refuse (SceneError) a ``section.key`` that names no scene key."""
    _split_key(key)


def coerce(key: str, value):
    """``value`` as the scene would hold it for ``key`` (an integer for a
    float key becomes a float: 2 and 2.0 are one value); raises SceneError."""
    section, name = _split_key(key)
    hints = typing.get_type_hints(SECTIONS[section])
    if name not in hints:  # a law parameter: a number as a float, else as given
        is_number = isinstance(value, (int, float)) and not isinstance(value, bool)
        return _check_type(key, value, float) if is_number else value
    return _check_type(key, value, hints[name])


def to_dict(scene: Scene) -> dict:
    """Nested ``{section: {key: value}}`` of every key, unset optionals left out."""
    out = {}
    for section in SECTIONS:
        values = dataclasses.asdict(getattr(scene, section))
        if section == "contact":
            values.update(values.pop("parameters"))
            values.update(values.pop("tables"))
        out[section] = {k: (list(v) if isinstance(v, tuple) else v)
                        for k, v in values.items() if v is not None}
    return out


def to_toml(scene: Scene) -> str:
    return tomli_w.dumps(to_dict(scene))


def _positive(scene, key, allow_zero=False):
    value = scene.get(key)
    if value < 0 or (value == 0 and not allow_zero):
        raise SceneError(key, f"must be {'>= 0' if allow_zero else '> 0'}, got {value}")


def validate(scene: Scene) -> None:
    """Refuse physically invalid or unrunnable values (docs/scenes.md)."""
    for key, choices in CHOICES.items():
        if scene.get(key) not in choices:
            raise SceneError(key, f"must be one of {', '.join(choices)}, got {scene.get(key)!r}")
    for key in ("body.mass", "body.E", "contact.F_N", "drive.k_d", "drive.v_d",
                "vibration.f", "time.T", "time.dt", "time.series_dt"):
        _positive(scene, key)
    for key in ("body.gravity",
                "vibration.k_v", "vibration.t_on", "fem.damping", "fem.output_every"):
        _positive(scene, key, allow_zero=True)
    if any(v <= 0 for v in scene.body.size):
        raise SceneError("body.size", f"every edge must be > 0, got {list(scene.body.size)}")
    if scene.body.density is not None and scene.body.density <= 0:
        raise SceneError("body.density", f"must be > 0, got {scene.body.density}")
    if not -1.0 < scene.body.nu < 0.5:
        raise SceneError("body.nu", f"must lie in (-1, 0.5), got {scene.body.nu}")
    if not 0.0 <= scene.contact.eta_y <= 1.0:
        raise SceneError("contact.eta_y", f"must lie in [0, 1], got {scene.contact.eta_y}")
    if scene.fem.penalty is not None and scene.fem.penalty <= 0:
        raise SceneError("fem.penalty", f"must be > 0, got {scene.fem.penalty}")
    if not 0.0 <= scene.fem.rho_infinity <= 1.0:
        raise SceneError("fem.rho_infinity", f"must lie in [0, 1], got {scene.fem.rho_infinity}")
    if scene.fem.cutoff < 0:
        raise SceneError("fem.cutoff", f"must be >= 0, got {scene.fem.cutoff}")
    if not 0.0 < scene.fem.accuracy < 1.0:
        raise SceneError("fem.accuracy", f"must lie in (0, 1), got {scene.fem.accuracy}")
    if scene.time.steady_tolerance < 0:
        raise SceneError("time.steady_tolerance", f"must be >= 0, got {scene.time.steady_tolerance}")
    if scene.time.steady_cycles < 0:
        raise SceneError("time.steady_cycles", f"must be >= 0, got {scene.time.steady_cycles}")
    if scene.time.average_cycles < 0:
        raise SceneError("time.average_cycles", f"must be >= 0, got {scene.time.average_cycles}")
    if scene.time.dt > scene.time.T:
        raise SceneError("time.dt", f"{scene.time.dt} is longer than time.T = {scene.time.T}")
    if scene.time.series_dt > scene.time.T:
        raise SceneError("time.series_dt", f"{scene.time.series_dt} s is longer than time.T = "
                                           f"{scene.time.T} s: the time series would hold no row")
    if not 0.0 < scene.time.settle_tolerance < 1.0:
        raise SceneError("time.settle_tolerance",
                         f"must lie in (0, 1), got {scene.time.settle_tolerance}")
    try:
        level_counts(scene.fem.mesh)
    except ValueError as err:
        raise SceneError("fem.mesh", str(err)) from None
    flat = {f"{section}.{k}": v for section, keys in to_dict(scene).items() for k, v in keys.items()}
    if (refusal := nonsense(flat)) is not None:
        raise SceneError(*refusal)
    try:  # a law file's first steps at the scene's values, bounds-checked (friction_law.law_check)
        law = load_law(scene.contact.law)   # (not scene.friction: a Scene stays picklable)
        law.probe(ContactLaw(law, law.values(scene.contact.given), scene.contact.F_N),
                  scene.time.dt)
    except LawError as err:
        raise law_refused(err) from None
    if scene.vibrated:
        vib, time = scene.vibration, scene.time
        if time.T <= vib.t_on:
            raise SceneError("time.T", f"{time.T} s ends before the vibration starts "
                                       f"(vibration.t_on = {vib.t_on} s)")
        steps_per_cycle = 1.0 / (vib.f * time.dt)
        if steps_per_cycle < 10:
            raise SceneError("time.dt", f"{time.dt} s resolves a vibration cycle of 1/f = "
                                        f"{1 / vib.f:.3g} s in {steps_per_cycle:.3g} steps; "
                                        "at least 10 are needed")
        cycles = scene.averaged_cycles
        window = cycles / vib.f
        if time.T - vib.t_on < window:
            raise SceneError("time.average_cycles",
                             f"{cycles} cycles ({window:.3g} s) do not fit between "
                             f"vibration.t_on = {vib.t_on} s and time.T = {time.T} s")
