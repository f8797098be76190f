"""The scene reference tables of docs/scenes.md, generated from the code.

    python docs/tools/scene_reference.py          # rewrites them in docs/scenes.md

docs/scenes.md holds the tables between the lines ``<!-- scene-keys -->`` and
``<!-- /scene-keys -->``: one per scene section, from the scene's dataclasses
(vibrofric/scene/schema.py: each key's type, default and the comment beside it,
read by vibrofric/scene/reference.py, the same rows ``vibrofric keys`` prints),
and one per built-in friction law, from its PARAMETERS. They are committed, so the
page reads whole on the forge too; tests/test_docs.py checks they are current
(run this script after changing a key).
"""

import inspect
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))   # the checkout this page documents, before any installed copy

PAGE = ROOT / "docs" / "scenes.md"
BEGIN, END = "<!-- scene-keys -->", "<!-- /scene-keys -->"


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


def section_table(section: str) -> str:
    from vibrofric.scene.reference import section_keys

    rows = ["| key | type | default | unit | meaning |", "|---|---|---|---|---|"]
    for key in section_keys(section):
        rows.append(f"| `{key.key}` | {key.type} | {_value(key.default)} | {key.unit or '-'} "
                    f"| {_cell(key.meaning)} |")
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
        parts.append(section_table(name) + "\n")
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


def page_with_reference(page: str) -> str:
    """``page`` (docs/scenes.md's text) with the tables between BEGIN and END made anew."""
    head, begin, rest = page.partition(BEGIN)
    _, end, tail = rest.partition(END)
    if not (begin and end):
        raise ValueError(f"{PAGE} lacks the lines {BEGIN} and {END}")
    return f"{head}{BEGIN}\n\n{scene_reference()}\n{END}{tail}"


if __name__ == "__main__":
    PAGE.write_text(page_with_reference(PAGE.read_text()))
