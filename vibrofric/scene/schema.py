"""What a scene holds: its sections as dataclasses, each key with its default (the
paper's longitudinal case, docs/model.md section 4), the quantities derived from
them (docs/model.md section 1), and the ``section.key`` names that address them.

docs/scenes.md's reference tables are generated from these dataclasses (each
key's type, default and the comment beside it: scene/reference.py,
docs/tools/scene_reference.py).
"""

import dataclasses
import functools
import math
import typing
from dataclasses import dataclass, field, fields
from pathlib import Path

from ..core.base_table import Harmonic
from ..core.bounce import bounce_stiffness, default_penalty
from ..friction_law import ContactLaw, load_law
from ..friction_law.contract import is_law_file
from .errors import SceneError


@dataclass(frozen=True)
class Body:
    shape: str = "block"                   # "block" | "cylinder" (a pin on its flat end) |
                                           # "ball" | "roller" (a cylinder on its side, axis
                                           # along Y); FE meshes: vibrofric/meshes/shapes.py
    mesh: typing.Optional[str] = None      # the user's own body instead: a .msh, .geo or .step
                                           # file (relative to the scene file) whose Physical
                                           # Surface "contact" names the facets that may touch
                                           # the base, optionally "load" and "drive"
                                           # (docs/your-own-body.md)
    radius: typing.Optional[float] = None  # m: cylinder, ball and roller (required by them)
    height: typing.Optional[float] = None  # m: the cylinder's (required by it)
    length: typing.Optional[float] = None  # m: the roller's, along Y (required by it)
    edge_radius: float = 0.0               # m: the rounding of the cylinder's contact edge; 0:
                                           # sharp
    hemisphere: bool = False               # ball: its lower half only, pole down, loaded on
                                           # its flat equator face
    mass: float = 0.5                      # kg, the body's mass
    size: tuple = (0.03, 0.04, 0.053)      # m: the block's X (sliding), Y, Z (height)
    E: float = 209e9                       # Pa, the body's Young's modulus
    nu: float = 0.3                        # the body's Poisson's ratio
    density: typing.Optional[float] = None  # kg/m^3; default mass / volume
    gravity: float = 9.81                  # m/s^2, acting in -Z

    @property
    def is_block(self) -> bool:
        """Whether the body is the paper's block (no mesh of the user's, shape "block")."""
        return self.mesh is None and self.shape == "block"


# The [body] keys each shape takes (required, optional) beside mass, E, nu, density and
# gravity: a key set for another shape is refused, never ignored (validation.py).
SHAPE_KEYS = {"block": (("size",), ()), "cylinder": (("radius", "height"), ("edge_radius",)),
              "ball": (("radius",), ("hemisphere",)), "roller": (("radius", "length"), ())}


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
    k_n: typing.Optional[float] = None     # the lumped body's normal contact stiffness; default:
                                           # it bounces at the FE block's first bounce frequency on
                                           # its penalty contact fem.penalty (core/bounce.py);
                                           # a body other than the block sets it to move the
                                           # base along Z
    zeta_n: float = 0.02                   # the lumped body's normal contact damping ratio: its
                                           # dashpot c_n = 2 zeta_n sqrt(k_n m) (analytic/normal.py;
                                           # the FE contact's dashpots are fem.damping's)
    parameters: dict = field(default_factory=dict)  # [contact]'s law parameters
    tables: dict = field(default_factory=dict)      # {law_key: {parameter: value}}

    def __hash__(self):
        """A contact is a value: hashed by its keys, its law's parameters and tables (dicts,
        which the generated hash of a frozen dataclass cannot take), as == compares them."""
        tables = tuple(sorted((name, tuple(sorted(table.items())))
                              for name, table in self.tables.items()))
        return hash((self.law, self.F_N, self.eta_y, self.k_n, self.zeta_n, tuple(sorted(self.parameters.items())),
                     tables))

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


CONTACT_KEYS = ("law", "F_N", "eta_y", "k_n", "zeta_n")     # the model's keys in [contact]; the rest are the law's


@dataclass(frozen=True)
class Drive:
    k_d: float = 96068.0                   # N/m, the drive spring's stiffness
    v_d: float = 5e-4                      # m/s, the drive's speed
    attach: str = "contact-plane"          # "contact-plane" | "front-face" | "drive-group" |
                                           # "load-group" (FE only: the facet group "contact",
                                           # "front", "drive" or "load" of the body's mesh;
                                           # fem/model/drive.py)
    holder: str = "none"                   # "none" | "translating" (FE only): the attachment's
                                           # group moves as one rigid translation, without
                                           # turning, as in a tribometer's holder; not with
                                           # "contact-plane" (fem/model/holder.py)
    mode: str = "spring"                   # "spring" | "velocity"

    @property
    def prescribed(self) -> bool:
        """mode "velocity": the attachment moves at exactly v_d, no spring."""
        return self.mode == "velocity"


@dataclass(frozen=True)
class Vibration:
    f: float = 4000.0                      # Hz, the base's vibration frequency
    k_v: float = 6.0                       # v_a / v_d; 0 means no vibration
    theta_deg: float = 0.0                 # angle of the vibration axis to X
    t_on: float = 0.14                     # s, when the vibration starts
    normal_amplitude: float = 0.0          # the base's motion along Z, A_n sin(w (t - t_on) + phase);
                                           # 0: none (analytic/normal.py, fem/model/contact.py)
    normal_phase_deg: typing.Optional[float] = None  # the normal motion's phase against the
                                           # in-plane motion (90: elliptical); none: 0, and only
                                           # with a normal_amplitude
    harmonics: typing.Tuple[Harmonic, ...] = ()  # harmonics added to the base's motion, each
                                           # { order = n, x = m, y = m, z = m, phase_x_deg,
                                           # phase_y_deg, phase_z_deg } at n f
                                           # (core/base_table.py); none: the sine alone
    motion: typing.Optional[str] = None    # a measured base motion instead of the sine: a CSV
                                           # file (relative to the scene file) with a header
                                           # t, x_b, y_b[, z_b] (s from t_on, m); k_v is 0
                                           # with it, and a k_v, normal_amplitude or harmonics
                                           # beside it are refused; FE: every
                                           # integrator (core/base_table.py)
    motion_periodic: bool = False          # the motion file spans one period, its last row the
                                           # next period's first, repeated (its frequency
                                           # replaces vibration.f); false: after the file ends
                                           # the base holds its last position (stepped only)

    @property
    def sampled(self) -> bool:
        """Whether the base's motion is given per step (a measured motion or harmonics,
        core/base_table.py), read from a table by the stepper."""
        return self.motion is not None or bool(self.harmonics)

    @property
    def repeats(self) -> bool:
        """Whether the base's motion is periodic (the periodic solver's premise): all but
        a measured motion that ends (motion_periodic false)."""
        return self.motion is None or self.motion_periodic


@dataclass(frozen=True)
class Time:
    T: float = 1.0                         # s, simulated time
    dt: float = 1e-6                       # s, the time step
    average_cycles: int = 0                # vibration cycles at the end averaged into F_dv;
                                           # 0: those nearest one drive-system period
    series_dt: float = 1e-5                # s, sampling of the written time series
    steady_tolerance: float = 0.0          # FE: stop once the window-averaged drive force changes
                                           # by at most this fraction over steady_cycles cycles;
                                           # 0: run to T (fem/outputs/steady.py)
    steady_cycles: int = 0                 # vibration cycles the settled average must hold;
                                           # 0: those of the averaging window
    settle_tolerance: float = 0.005        # a stepped result is "settled" when the drift of its
                                           # drive-force mean still to come, from the decay of
                                           # successive windows' means, is at most this fraction
                                           # (core/settling.py)
    method: str = "auto"                   # "auto" or "periodic": the steady cycle by shooting
                                           # (analytic/periodic.py, fem/integrators/periodic.py),
                                           # stepped through T where it does not converge or is
                                           # not stable, saying so; "transient": step through T
    accuracy: float = 1e-3                 # the error of F_dv / F_d0 (absolute) an answer should
                                           # meet: one whose estimate exceeds it is given with a
                                           # warning naming a step that meets it
                                           # (analytic/accuracy.py); FE: fem.integrator "auto"
                                           # refines its step until its estimate does
                                           # (fem/step_error.py)
    error_estimate: typing.Union[str, bool] = "auto"  # FE: the step's error from a second run at
                                           # dt / 2. true: always; false: never; "auto": where that
                                           # is cheap, a steady cycle (time.method periodic / auto)
                                           # on the coarse mesh or a coarser one (fem/step_error.py);
                                           # and the mesh's error where another level's block is
                                           # cached (fem/simulate.py mesh_error)


@dataclass(frozen=True)
class Fem:
    mesh: str = "coarse"                   # refinement level, see vibrofric.meshes
    integrator: str = "explicit"           # "explicit" | "implicit" | "reduced" | "auto"
                                           # (fem/integrators/registry.py)
    penalty: typing.Optional[float] = None  # N/m for the whole contact face (spread by area);
                                           # default: contact_stiffness's
    contact_stiffness: typing.Optional[float] = None  # the penalty per unit contact area, Pa/m;
                                           # default 10 E / H, H the body's height (the block's
                                           # 10 E A / L_z on its face A), on a curved contact
                                           # at least 100 E* / a, a Hertz's contact radius
                                           # (fem/model/contact.py)
    output_every: int = 2000               # steps between ParaView frames; 0: none
    damping: float = 0.0                   # stiffness-proportional damping beta, s; 0: 6% at the top mode
    rho_infinity: float = 0.9              # implicit, reduced: generalized-alpha's spectral radius at
                                           # infinite frequency; 1 = trapezoidal rule (fem/integrators/implicit.py)
    cutoff: float = 12.0                   # reduced: keep the block's fixed-interface modes below
                                           # cutoff * vibration.f (fem/integrators/reduction.py)
    interface_reach: typing.Union[float, str] = 3.0  # reduced: the contact candidates kept on
                                           # the interface: the preload's patch and those whose
                                           # gap at rest is within reach times the patch edge's
                                           # (3: a Hertz patch under up to 5.2 F_N); the others
                                           # are watched, and a run where one touches stops;
                                           # "all": every candidate (fem/integrators/interface.py)
    accuracy: float = 0.01                 # auto: the reduced model's estimated error of F_dv (relative)
                                           # it accepts (fem/integrators/registry.py); its step
                                           # meets time.accuracy
    energy: bool = False                   # implicit, reduced: record the energy balance
                                           # (fem/outputs/energy.py)
    normal_force: str = "nodal"            # the normal force each node's friction law sees:
                                           # "nodal", its own penalty force; "nominal", its
                                           # share F_N a_i / A while in contact (the paper's
                                           # constant pressure; fem/model/contact.py)


SECTIONS = {"body": Body, "contact": Contact, "drive": Drive,
            "vibration": Vibration, "time": Time, "fem": Fem}

CHOICES = {
    "body.shape": tuple(SHAPE_KEYS),
    "drive.attach": ("contact-plane", "front-face", "drive-group", "load-group"),
    "drive.holder": ("none", "translating"),
    "drive.mode": ("spring", "velocity"),
    "fem.integrator": ("explicit", "implicit", "reduced", "auto"),
    "fem.normal_force": ("nodal", "nominal"),
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
    @property
    def friction(self) -> ContactLaw:
        """The contact's friction law with its parameter values (friction_law.ContactLaw).

        Made on each call (contact_law), never kept in the scene: a Scene is a value, which
        pickles, compares and hashes the same before and after any run, and the loaded
        law holds its module, which does not pickle."""
        return contact_law(self.contact)

    @property
    def law_bounds(self):
        """What the integrators need of the law at time.dt (friction_law.Bounds)."""
        return self.friction.bounds(self.time.dt)

    @property
    def vibrated(self) -> bool:
        """Whether the base moves: in the plane (k_v > 0), along Z (normal_amplitude > 0), or
        as a measured motion or harmonics give it."""
        return (self.vibration.k_v > 0.0 or self.vibration.normal_amplitude > 0.0
                or self.vibration.sampled)

    @property
    def normal_stiffness(self) -> float:
        """The lumped body's normal contact stiffness k_n, N/m: contact.k_n, or the one
        on which it bounces at the FE block's first bounce frequency on its penalty
        contact (fem.penalty or its default; core/bounce.py)."""
        if self.contact.k_n is not None:
            return self.contact.k_n
        body = self.body
        a, b, c = body.size
        density = body.density if body.density is not None else body.mass / (a * b * c)
        return bounce_stiffness(body.mass, body.E, density, body.size, self.block_penalty)

    @property
    def block_penalty(self) -> float:
        """The FE block's penalty stiffness of its whole contact face, N/m: fem.penalty,
        else its default (core/bounce.py default_penalty, the FE model's on the block)."""
        if self.fem.penalty is not None:
            return self.fem.penalty
        return default_penalty(self.body.E, self.body.size)

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
        section, name = split_key(key)
        if "." in name:  # contact.<law>.<parameter>: that law's table
            law, name = name.split(".")
            return self.contact.tables.get(law, {}).get(name)
        return getattr(getattr(self, section), name)

    def with_values(self, values: dict) -> "Scene":
        """A copy with ``{"section.key": value}`` set and checked."""
        from .build import from_dict   # (build and keys import this module)
        from .keys import assign

        raw = to_dict(self)
        for key, value in values.items():
            assign(raw, key, value)
        return from_dict(raw, self.name)

    def with_law(self, law: str, parameters: dict | None = None) -> "Scene":
        """A copy with another friction law and ``parameters`` for it in its own table;
        [contact]'s shared keys stay (each must be a parameter of the new law)."""
        from .build import from_dict

        raw = to_dict(self)
        raw["contact"]["law"] = law
        if parameters:
            raw["contact"][law_key(law)] = {**raw["contact"].get(law_key(law), {}), **parameters}
        return from_dict(raw, self.name)


def contact_law(contact: Contact) -> ContactLaw:
    """The contact's law, loaded (friction_law.load_law keeps each law loaded once: a law
    file by its content, so an edited file is loaded anew), with its parameter values."""
    law = load_law(contact.law)
    return ContactLaw(law, law.values(contact.given), contact.F_N)


def split_key(key: str):
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
