"""The package's layers import one way: friction_law <- core <- {analytic, fem} <- the command.

Read from the source (ast), so a lazy import inside a function counts too.
"""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "vibrofric"

# What each layer must never import (package-relative module names, and libraries).
FORBIDDEN = {
    "friction_law": {"core", "analytic", "fem", "batch", "cli", "dolfinx", "ufl", "petsc4py"},
    "core": {"analytic", "fem", "batch", "cli", "dolfinx", "ufl", "petsc4py"},
    "analytic": {"fem", "batch", "cli", "dolfinx", "ufl", "petsc4py"},
    "fem": {"analytic", "batch", "cli"},
}


def imported(path: Path) -> set:
    """Top names imported by a module: ``vibrofric.x`` and ``..x`` give ``x``, ``numpy`` gives ``numpy``."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                names.add(parts[1] if parts[0] == "vibrofric" and len(parts) > 1 else parts[0])
        elif isinstance(node, ast.ImportFrom):
            parts = (node.module or "").split(".")
            if node.level == 0:
                names.add(parts[1] if parts[0] == "vibrofric" and len(parts) > 1 else parts[0])
            elif node.level >= 2:  # from ..x import y: a sibling layer
                names.add(parts[0] if parts[0] else node.names[0].name)
    return names


@pytest.mark.parametrize("layer", sorted(FORBIDDEN))
def test_layer_imports_nothing_above_it(layer):
    modules = sorted((PACKAGE / layer).rglob("*.py"))
    assert modules
    offending = {str(path.relative_to(PACKAGE)): sorted(imported(path) & FORBIDDEN[layer])
                 for path in modules}
    assert {k: v for k, v in offending.items() if v} == {}


def test_the_check_sees_a_forbidden_import(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("def f():\n    from ..analytic.coupled import run_coupled\n"
                      "import vibrofric.batch\nfrom dolfinx import fem\n")
    assert {"analytic", "batch", "dolfinx"} <= imported(module)


@pytest.mark.parametrize("layer", ["friction_law", "core", "analytic", "fem"])
def test_only_the_scene_layer_names_scene_keys_in_errors(layer):
    """The numerics raise their own errors (core.errors); scene.REFUSAL_KEYS names the key."""
    raising = [str(path.relative_to(PACKAGE)) for path in sorted((PACKAGE / layer).rglob("*.py"))
               if "SceneError" in {getattr(node, "id", getattr(node, "attr", None))
                                   for node in ast.walk(ast.parse(path.read_text()))}]
    assert raising == []


def test_every_refusal_has_a_scene_key():
    from vibrofric.core import errors
    from vibrofric.scene import REFUSAL_KEYS

    refusals = {cls for cls in vars(errors).values()
                if isinstance(cls, type) and issubclass(cls, errors.Refusal) and cls is not errors.Refusal}
    assert refusals and refusals == set(REFUSAL_KEYS)
