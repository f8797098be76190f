"""The scene reference, generated when the site is built (a MkDocs hook).

The page docs/scenes.md holds the line ``<!-- scene-keys -->``; this hook puts
there a table per scene section, read from the scene's dataclasses
(vibrofric/scene/schema.py: each key's type, default and the comment beside it), and
one per built-in friction law, read from its PARAMETERS (friction_law/). A key
added to the code appears in the docs at the next build.
"""

import dataclasses
import inspect
import math
import re
import sys
import typing
from pathlib import Path

# the checkout this site documents, before any installed copy of the package
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

MARKER = "<!-- scene-keys -->"
# ``    name: type = default   # comment`` and the comment lines under it
FIELD = re.compile(r"^\s+(\w+)\s*:[^=#]+(?:=[^#]*)?(?:#\s?(.*))?$")
CONTINUATION = re.compile(r"^\s+#\s?(.*)$")


def field_comments(cls) -> dict:
    """{field name: the comment written beside it, continuation lines joined}."""
    comments, current = {}, None
    for line in inspect.getsource(cls).splitlines()[1:]:
        field = FIELD.match(line)
        if field and not line.lstrip().startswith(("def ", "@", "#")):
            current = field.group(1)
            comments[current] = (field.group(2) or "").strip()
            continue
        more = CONTINUATION.match(line)
        if more and current is not None:
            comments[current] = f"{comments[current]} {more.group(1).strip()}".strip()
        elif line.strip():
            current = None
    return comments


def _type_name(annotation) -> str:
    if typing.get_origin(annotation) is typing.Union:
        choices = typing.get_args(annotation)
        if type(None) not in choices:
            return " or ".join(t.__name__ for t in choices)
        return f"{choices[0].__name__} (optional)"
    return {tuple: "3 numbers"}.get(annotation, getattr(annotation, "__name__", str(annotation)))


def _value(value) -> str:
    if value is None:
        return "derived"
    if isinstance(value, str):
        return f'`"{value}"`'
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, tuple):
        return "`[" + ", ".join(f"{v:g}" for v in value) + "]`"
    if isinstance(value, float):
        return f"`{value:g}`"
    return f"`{value}`"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def section_table(name: str, cls, choices: dict, skip=()) -> str:
    hints = typing.get_type_hints(cls)
    comments = field_comments(cls)
    rows = ["| key | type | default | meaning |", "|---|---|---|---|"]
    for field in dataclasses.fields(cls):
        if field.name in skip:
            continue
        default = field.default if field.default is not dataclasses.MISSING else field.default_factory()
        meaning = comments.get(field.name, "")
        if f"{name}.{field.name}" in choices:
            meaning = meaning.rstrip(". ") + ("; one of " if meaning else "One of ")
            meaning += "" + ", ".join(f'`"{c}"`' for c in choices[f"{name}.{field.name}"]) + "."
        rows.append(f"| `{name}.{field.name}` | {_type_name(hints[field.name])} | {_value(default)} "
                    f"| {_cell(meaning.strip())} |")
    return "\n".join(rows)


def _range(parameter) -> str:
    if parameter.choices:
        return ", ".join(f'`"{c}"`' for c in parameter.choices)
    low, high = parameter.low, parameter.high
    if low == -math.inf and high == math.inf:
        return "any"
    left = "(" if parameter.low_open else "["
    right = "]" if high != math.inf else ")"
    return f"{left}{low:g}, {'inf' if high == math.inf else format(high, 'g')}{right}"


def law_table(law) -> str:
    rows = ["| key | unit | default | valid | meaning |", "|---|---|---|---|---|"]
    for name, parameter in law.parameters.items():
        rows.append(f"| `contact.{name}` | {parameter.unit or '-'} | {_value(parameter.default)} "
                    f"| {_range(parameter)} | {_cell(parameter.doc)} |")
    return "\n".join(rows)


def scene_reference() -> str:
    """The generated Markdown: every scene section, then every built-in law's keys."""
    from vibrofric import scene
    from vibrofric.friction_law import load_law
    from vibrofric.friction_law.contract import BUILT_IN

    parts = []
    for name, cls in scene.SECTIONS.items():
        doc = inspect.getdoc(cls) if cls.__doc__ else ""
        parts.append(f"### `[{name}]`\n")
        if doc and not doc.startswith(cls.__name__ + "("):
            parts.append(doc + "\n")
        skip = ("parameters",) if name == "contact" else ()
        parts.append(section_table(name, cls, scene.CHOICES, skip) + "\n")
    parts.append("## Friction-law parameters\n")
    parts.append("Every other key of `[contact]` is a parameter of the scene's law "
                 "(`contact.law`). The built-in laws:\n")
    for name in BUILT_IN:
        law = load_law(name)
        parts.append(f'### `contact.law = "{name}"`\n')
        summary = (inspect.getdoc(law.module) or "").split("\n\n")[0]
        if summary:
            parts.append(summary + "\n")
        parts.append(law_table(law) + "\n")
    return "\n".join(parts)


def on_page_markdown(markdown, page, config, files):  # the MkDocs hook
    if MARKER in markdown:
        return markdown.replace(MARKER, scene_reference())
    return markdown


if __name__ == "__main__":
    print(scene_reference())
