"""The package's layers import one way, from the command down to the friction law.

Every module of vibrofric sits on one floor and imports only from the floors
below it (and from inside its own package): friction_law <- core <- analytic,
fem <- fe_beside_analytic <- batch, bench <- api <- cli. Read from the source (ast), so a
lazy import inside a function counts too.
"""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "vibrofric"

# Bottom to top. A floor's packages and modules never import each other (the
# analytic and the FE models stay independent), only what lies below.
FLOORS = (
    {"disk_cache", "library_logs", "parallel", "sense", "picture", "answer_text"},  # helpers that import no vibrofric module
    {"friction_law"},
    {"core"},
    {"meshes"},                                       # the body's meshes (refusals: core.errors)
    {"analytic", "fem", "scene"},                     # the two models; the scene file
    {"grid", "output", "plots"},                      # what a run reads and writes
    {"fe_beside_analytic", "plot_worker", "warm"},                  # a run of each model, side by side
    {"budget"},
    {"batch", "bench"},                               # studies: sweeps, speed against error
    {"api"},
    {"cli"},
)
FLOOR = {name: level for level, names in enumerate(FLOORS) for name in names}
# DOLFINx and its Python companions are imported by one module only.
DOLFINX = {"dolfinx", "ufl", "petsc4py", "basix", "ffcx"}
DOLFINX_ADAPTER = "fem/model/dolfinx_adapter.py"


def package_of(path: Path) -> tuple:
    """The module's package inside vibrofric: () for vibrofric/x.py, ("fem",) for fem/x.py."""
    return path.relative_to(PACKAGE).parts[:-1]


def imported(path: Path, package: tuple = ("layer",)) -> set:
    """Top names imported by a module of ``package``: ``vibrofric.x.y``, ``..x`` (from a
    subpackage) and ``.x`` (from a top-level module) give ``x``; ``numpy`` gives ``numpy``."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                names.add(parts[1] if parts[0] == "vibrofric" and len(parts) > 1 else parts[0])
        elif isinstance(node, ast.ImportFrom):
            parts = (node.module or "").split(".") if node.module else []
            if node.level == 0:
                names.add(parts[1] if parts[0] == "vibrofric" and len(parts) > 1 else parts[0])
                continue
            full = list(package[:len(package) - (node.level - 1)]) + parts
            names.update([full[0]] if full else [alias.name for alias in node.names])
    return names


def modules():
    return sorted(path for path in PACKAGE.rglob("*.py") if path != PACKAGE / "__init__.py")


def top(path: Path) -> str:
    """The top-level name a module belongs to: its package, or itself."""
    return path.relative_to(PACKAGE).parts[0].removesuffix(".py")


def test_every_module_is_on_a_floor():
    assert sorted({top(path) for path in modules()} - set(FLOOR)) == []
    assert sorted(set(FLOOR) - {top(path) for path in modules()}) == []


@pytest.mark.parametrize("name", sorted(FLOOR))
def test_a_module_imports_only_the_floors_below(name):
    offending = {}
    for path in modules():
        if top(path) != name:
            continue
        above = {other for other in imported(path, package_of(path)) & set(FLOOR)
                 if other != name and FLOOR[other] >= FLOOR[name]}
        if str(path.relative_to(PACKAGE)) != DOLFINX_ADAPTER:
            above |= imported(path, package_of(path)) & DOLFINX
        if above:
            offending[str(path.relative_to(PACKAGE))] = sorted(above)
    assert offending == {}


def test_the_check_sees_a_forbidden_import(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("def f():\n    from ..analytic.coupled import run_coupled\n"
                      "import vibrofric.batch\nfrom dolfinx import fem\nfrom . import sibling\n")
    assert {"analytic", "batch", "dolfinx", "layer"} <= imported(module, ("layer",))
    assert {"analytic", "sibling"} <= imported(module, ())   # a top-level module's ".x" is x


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


# Inside fem, bottom to top: the model as arrays, what a run records, the integrators that
# step the model and record, the answer's step error (which answers to compare), and
# simulate (run_fe) on top.
FEM_FLOORS = ("model", "outputs", "integrators", "step_error", "simulate")


@pytest.mark.parametrize("name", FEM_FLOORS)
def test_fem_subpackages_import_only_the_ones_below(name):
    fem = PACKAGE / "fem"
    assert sorted(path.relative_to(fem).parts[0].removesuffix(".py") for path in fem.iterdir()
                  if path.suffix == ".py" or (path / "__init__.py").exists()) \
        == sorted(FEM_FLOORS + ("__init__",))
    offending = {}
    for path in sorted(fem.rglob("*.py")):
        package = package_of(path)
        if path.relative_to(fem).parts[0].removesuffix(".py") != name:
            continue
        names = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level > 0:
                full = list(package[:len(package) - (node.level - 1)]) + (node.module or "").split(".")
                if full[0] == "fem":
                    names.add(full[1] if len(full) > 1 and full[1] else None)
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("vibrofric.fem."):
                names.add(node.module.split(".")[2])
        above = {other for other in names - {None, name}
                 if other not in FEM_FLOORS or FEM_FLOORS.index(other) >= FEM_FLOORS.index(name)}
        if above:
            offending[str(path.relative_to(PACKAGE))] = sorted(above)
    assert offending == {}
