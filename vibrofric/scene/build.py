"""A Scene built from nested ``{section: {key: value}}``: each value checked against its
key's type, the contact's law parameters against the law's declaration, then the
whole scene validated."""

import dataclasses
import difflib
import typing

from ..core.base_table import WHOLE_STEPS, read_motion
from ..core.errors import BadBaseMotion
from ..friction_law import ContactLaw, LawError, ParameterError, load_law
from ..friction_law.contract import BUILT_IN
from .errors import SceneError, law_refused, refused
from .keys import check_type
from .schema import CONTACT_KEYS, SECTIONS, Contact, Scene, law_key, split_key
from .validation import validate


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
            section_, key_ = split_key(f"{section}.{key}")
            checked[key_] = check_type(f"{section}.{key}", value, hints[key_])
        if section == "vibration" and checked.get("motion") is not None:
            checked.setdefault("k_v", 0.0)      # a measured motion replaces the paper's sine
        sections[section] = SECTIONS[section](**checked)
    scene = Scene(name=name, **sections)
    if scene.vibration.motion is not None and scene.vibration.motion_periodic:
        scene = _with_motion_frequency(scene, "f" in raw.get("vibration", {}))
    validate(scene)
    return scene


def _with_motion_frequency(scene: Scene, f_given: bool) -> Scene:
    """A periodic measured motion's frequency, 1 / its file's span, as vibration.f (the
    periodic solver's cycle, the averaging window's cycles); a vibration.f the scene
    gives must be that one (to core.base_table.WHOLE_STEPS relative)."""
    try:
        span = read_motion(scene.vibration.motion).span
    except BadBaseMotion as err:
        raise refused(err) from None
    f = 1.0 / span
    if f_given and abs(scene.vibration.f - f) > WHOLE_STEPS * f:
        raise SceneError("vibration.f", f"{scene.vibration.f:g} Hz, but the periodic measured "
                                        f"motion's period {span:g} s makes it {f:.10g} Hz: "
                                        "remove vibration.f (the motion sets it)")
    return dataclasses.replace(scene, vibration=dataclasses.replace(scene.vibration, f=f))


def _contact(values: dict) -> Contact:
    """[contact]: the model's keys, then the law's parameters checked against its declaration:
    [contact]'s shared keys and the chosen law's table against the chosen law, every
    built-in law's table against that law (a typo is refused whichever law runs)."""
    hints = typing.get_type_hints(Contact)
    own = {key: check_type(f"contact.{key}", values[key], hints[key])
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
