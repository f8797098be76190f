import os
import pathlib
import signal

import numpy as np
import pytest

try:  # before anything imports dolfinx: the PyPI wheel finds its libmpi through mpi4py
    from mpi4py import MPI  # noqa: F401
except ImportError:  # the analytic model alone needs no MPI
    pass

from vibrofric import scene as scene_module
from vibrofric.core.errors import Refusal
from vibrofric.core.series import COLUMNS, PLOT_CYCLES, ROWS_PER_CYCLE, written_stride

SCENES = pathlib.Path(__file__).resolve().parent.parent / "scenes"
ROOT = SCENES.parent

# The variables an initialized MPI runtime leaves in its process's environment
# (mpi4py imported above starts Open MPI as a singleton: OMPI_MCA_ess, PMIX_*).
# A child given them believes it was launched by that runtime: Open MPI's
# mpirun exits 1 at once, the PyPI stack's MPICH aborts ("unsupported PMI
# version PMIx"). Seen under pytest-xdist's worker processes.
MPI_RUNTIME = ("OMPI_", "PMIX_", "PMI_")


def as_in_a_terminal():
    """A child's Ctrl-C as a command started from a terminal has it (``preexec_fn``): a
    test run started in the background (``make test &``, nohup) inherits SIGINT
    ignored, and Python then installs no handler for it, so a SIGINT sent to the
    child would do nothing."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def child_environment(**more) -> dict:
    """The environment for a child process running the project: this one's without
    the MPI runtime's variables, the source tree on PYTHONPATH, then ``more``."""
    env = {key: value for key, value in os.environ.items() if not key.startswith(MPI_RUNTIME)}
    return {**env, "PYTHONPATH": str(ROOT), **more}


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
            return scene_module.refused(error).key
        raise AssertionError("the scene was not refused")
    return key


@pytest.fixture(autouse=True)
def _at_repository_root(monkeypatch):
    """Tests name scenes as ``scenes/...``, as a user at the repository root would."""
    monkeypatch.chdir(SCENES.parent)


@pytest.fixture(scope="session")
def written_by_rule():
    """Check that a written time series (CSV) holds the default rows for the
    scene it was run with, core.series.written(): a row every written_stride
    steps, every step of the last PLOT_CYCLES cycles, at least ROWS_PER_CYCLE
    rows a vibration cycle. Returns the table read back."""
    def check(path, scene) -> np.ndarray:
        with open(path, newline="") as f:
            header = f.readline()
        assert header.split("\r\n")[0].split(",")[:len(COLUMNS)] == list(COLUMNS)
        table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
        t, f = table[:, 0], scene.vibration.f
        step = np.rint(t / scene.time.dt).astype(np.int64)
        last = t >= t[-1] - PLOT_CYCLES / f * (1 + 1e-9)
        stride = written_stride(scene)
        assert step[0] == stride and np.all(np.diff(step[~last]) == stride)
        assert np.all(np.diff(step[last]) == 1)
        assert step[last][0] <= step[~last][-1] + stride
        assert np.diff(t).max() <= 1.0 / (ROWS_PER_CYCLE * f) * (1 + 1e-9)
        return table
    return check


@pytest.fixture(scope="module")
def own_model_cache(tmp_path_factory):
    """The module's FE models in a cache of its own (a module asks for it with
    ``pytestmark = pytest.mark.usefixtures("own_model_cache")``): its bodies would take
    the place of a user's blocks in the shared one (model_cache.KEPT_ENTRIES)."""
    patch = pytest.MonkeyPatch()
    patch.setenv("VIBROFRIC_CACHE", str(tmp_path_factory.mktemp("cache")))
    yield
    patch.undo()
