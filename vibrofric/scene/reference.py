"""Every key of a scene, as a reader looks it up: its value, its default, its unit and
what it means (``vibrofric keys``, ``vibrofric.scene_keys``, the tables of
docs/scenes.md).

A section's keys are read from its dataclass (schema.py): the type, the default
and the comment written beside the field, which is the key's meaning; UNITS gives
the unit of each number. The law's keys are read from its PARAMETERS (unit,
default, ``doc``). A key added to the code is listed at once.
"""

import dataclasses
import inspect
import re
import typing
from dataclasses import dataclass

from .schema import CHOICES, SECTIONS, Scene, law_key

# The unit of every scene key that holds a number ("" for a ratio or a count of
# something the key names); a law's parameters carry their own (Parameter.unit).
UNITS = {
    "body.mass": "kg", "body.size": "m", "body.E": "Pa", "body.nu": "", "body.density": "kg/m^3",
    "body.gravity": "m/s^2", "body.radius": "m", "body.height": "m", "body.length": "m",
    "body.edge_radius": "m",
    "contact.F_N": "N", "contact.eta_y": "", "contact.k_n": "N/m",
    "contact.zeta_n": "",
    "drive.k_d": "N/m", "drive.v_d": "m/s",
    "vibration.f": "Hz", "vibration.k_v": "", "vibration.theta_deg": "deg", "vibration.t_on": "s",
    "vibration.normal_amplitude": "m", "vibration.normal_phase_deg": "deg",
    "vibration.harmonics": "m, deg",
    "time.T": "s", "time.dt": "s", "time.average_cycles": "cycles", "time.series_dt": "s",
    "time.steady_tolerance": "", "time.steady_cycles": "cycles", "time.settle_tolerance": "",
    "fem.penalty": "N/m", "fem.contact_stiffness": "Pa/m", "fem.output_every": "steps", "fem.damping": "s",
    "fem.rho_infinity": "", "fem.cutoff": "", "fem.interface_reach": "", "fem.accuracy": "",
}
# [contact]'s fields that hold the law's parameters, not keys of their own
LAW_FIELDS = ("parameters", "tables")

# ``    name: type = default   # comment`` and the comment lines under it
_FIELD = re.compile(r"^\s+(\w+)\s*:[^=#]+(?:=[^#]*)?(?:#\s?(.*))?$")
_CONTINUATION = re.compile(r"^\s+#\s?(.*)$")


@dataclass(frozen=True)
class Key:
    """One scene key: ``key`` as ``--set`` names it, the scene's ``value``, the
    ``default``, the ``unit`` ("" for none), its ``meaning`` and its type."""

    key: str
    value: object
    default: object
    unit: str
    meaning: str
    type: str


def field_comments(cls) -> dict:
    """{field name: the comment written beside it in the class, continuation lines joined}."""
    comments, current = {}, None
    for line in inspect.getsource(cls).splitlines()[1:]:
        field = _FIELD.match(line)
        if field and not line.lstrip().startswith(("def ", "@", "#")):
            current = field.group(1)
            comments[current] = (field.group(2) or "").strip()
            continue
        more = _CONTINUATION.match(line)
        if more and current is not None:
            comments[current] = f"{comments[current]} {more.group(1).strip()}".strip()
        elif line.strip():
            current = None
    return comments


def type_name(annotation) -> str:
    if typing.get_origin(annotation) is typing.Union:
        choices = typing.get_args(annotation)
        if type(None) not in choices:
            return " or ".join(t.__name__ for t in choices)
        return f"{choices[0].__name__} (optional)"
    if typing.get_origin(annotation) is tuple:
        return "list of tables"
    return {tuple: "3 numbers"}.get(annotation, getattr(annotation, "__name__", str(annotation)))


def section_keys(section: str, scene: Scene | None = None) -> list:
    """The keys of one section (without the law's parameters), at ``scene``'s values
    (None: the defaults)."""
    cls = SECTIONS[section]
    hints = typing.get_type_hints(cls)
    comments = field_comments(cls)
    keys = []
    for field in dataclasses.fields(cls):
        if section == "contact" and field.name in LAW_FIELDS:
            continue
        name = f"{section}.{field.name}"
        default = field.default if field.default is not dataclasses.MISSING \
            else field.default_factory()
        unit = UNITS.get(name, "")
        meaning = comments.get(field.name, "")
        if unit and re.match(rf"{re.escape(unit)}(\Z|[,;:] )", meaning):   # the unit column's
            meaning = meaning[len(unit):].lstrip(",;: ")
        if name in CHOICES and not all(f'"{c}"' in meaning for c in CHOICES[name]):
            meaning = meaning.rstrip(". ") + ("; one of " if meaning else "One of ")
            meaning += ", ".join(f'"{choice}"' for choice in CHOICES[name])
        value = getattr(getattr(scene, section), field.name) if scene is not None else default
        keys.append(Key(name, value, default, unit, meaning, type_name(hints[field.name])))
    return keys


def law_keys(law, values: dict | None = None, table: str = "") -> list:
    """The parameters of a loaded law (friction_law.FrictionLaw) as ``contact.<name>``
    (``contact.<table>.<name>`` for a law's own table), at ``values`` (None: defaults)."""
    prefix = f"contact.{table}." if table else "contact."
    keys = []
    for name, parameter in law.parameters.items():
        value = parameter.default if values is None else values.get(name, parameter.default)
        kind = "string" if parameter.choices else "float"
        keys.append(Key(prefix + name, value, parameter.default, parameter.unit, parameter.doc,
                        kind))
    return keys


def scene_keys(scene: Scene) -> list:
    """Every key of ``scene``: each section's, then its law's parameters (contact.<name>:
    [contact]'s or the law's own table's value, else the default), then the values of
    other laws' tables the scene holds (contact.<law>.<name>, applied only under that
    law)."""
    from ..friction_law import load_law
    from ..friction_law.contract import BUILT_IN

    keys = []
    for section in SECTIONS:
        keys.extend(section_keys(section, scene))
        if section == "contact":
            keys.extend(law_keys(scene.friction.law, scene.contact.law_values))
            chosen = law_key(scene.contact.law)
            for table, values in scene.contact.tables.items():
                if table == chosen:
                    continue
                if table in BUILT_IN:   # (checked against that law when the scene was built)
                    keys.extend(key for key in law_keys(load_law(table), values, table)
                                if key.key.rpartition(".")[2] in values)
                else:   # a law file's table, checked when that law runs
                    keys.extend(Key(f"contact.{table}.{name}", value, None, "", "", "")
                                for name, value in values.items())
    return keys
