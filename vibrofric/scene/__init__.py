"""Scenes: the physics of one study case plus the numerics that run it.

A scene is a TOML file with the sections of docs/scenes.md. Every key has a
default (the paper's longitudinal case, docs/model.md section 4), so a file
holds only what differs; ``--set section.key=value`` overrides any key. Every
value is checked before any work: a bad one raises ``SceneError`` naming it.

    >>> from vibrofric import scene
    >>> s = scene.from_dict({"vibration": {"k_v": 2}})   # every other key its default
    >>> s.vibration.k_v, s.v_a       # the base's velocity amplitude k_v v_d (eq 27), m/s
    (2.0, 0.001)
    >>> s.with_values({"drive.v_d": 1e-3}).v_a
    0.002

The package, by idea:

    schema      the sections and their defaults, the Scene and what derives from it,
                ``section.key`` names
    keys        one key set: ``--set`` parsed, its value type-checked
    build       a Scene from nested dicts, the law's parameters checked
    validation  every value of a built scene checked
    toml_io     scene files read and written
    reference   every key of a scene: its value, default, unit and meaning
    errors      SceneError, and the model's refusals as scene keys
"""

from .build import from_dict
from .errors import REFUSAL_KEYS, SceneError, law_refused, refused
from .keys import check_key, coerce, parse_assignment, parse_value
from .schema import (CHOICES, CONTACT_KEYS, SECTIONS, Body, Contact, Drive, Fem, Scene, Time,
                     Vibration, law_key, to_dict)
from .toml_io import load, to_toml
from .validation import check_fe_scene, validate

__all__ = ["CHOICES", "CONTACT_KEYS", "REFUSAL_KEYS", "SECTIONS", "Body", "Contact", "Drive",
           "Fem", "Scene", "SceneError", "Time", "Vibration", "check_fe_scene", "check_key", "coerce", "from_dict",
           "law_key", "law_refused", "load", "parse_assignment", "parse_value", "refused",
           "to_dict", "to_toml", "validate"]
