import pathlib

import pytest

try:  # before anything imports dolfinx: the PyPI wheel finds its libmpi through mpi4py
    from mpi4py import MPI  # noqa: F401
except ImportError:  # the analytic model alone needs no MPI
    pass

from vibrofric import scene as scene_module
from vibrofric.core.errors import Refusal

SCENES = pathlib.Path(__file__).resolve().parent.parent / "scenes"


@pytest.fixture(scope="session")
def load_scene():
    """Load a shipped scene by name, with ``{"section.key": value}`` changes."""
    def load(name, **changes):
        scene = scene_module.load(SCENES / f"{name}.toml")
        return scene.with_values({k.replace("__", "."): v for k, v in changes.items()})
    return load


@pytest.fixture(scope="session")
def refused_key():
    """The scene key under which ``run()`` is refused: a SceneError's own key, or
    the key the scene layer names for the model's refusal (scene.REFUSAL_KEYS)."""
    def key(run) -> str:
        try:
            run()
        except scene_module.SceneError as error:
            return error.key
        except Refusal as error:
            return scene_module.REFUSAL_KEYS[type(error)]
        raise AssertionError("the scene was not refused")
    return key


@pytest.fixture(autouse=True)
def _at_repository_root(monkeypatch):
    """Tests name scenes as ``scenes/...``, as a user at the repository root would."""
    monkeypatch.chdir(SCENES.parent)
