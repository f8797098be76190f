"""A user's law through its pointer (friction_law/through_pointer.py): the loops compiled
once for every law give the specialized loops' answers, a law's exception is blamed on
the law, a new law's first run leaves its specialization for after the run, sweeps run
the specialized loops, and the warm-up covers every shipped scene."""

import uuid
from pathlib import Path

import numpy as np
import pytest

from vibrofric import scene as scene_module
from vibrofric import warm
from vibrofric.analytic.coupled import coupled_loop, run_coupled
from vibrofric.batch import in_memory, study
from vibrofric.friction_law import specialize, specialize_later
from vibrofric.friction_law.contract import LawError

ROOT = Path(__file__).resolve().parents[1]
LAWS = ROOT / "examples" / "laws"

# A law that counts its calls in its state and raises at the thousandth: past the first
# steps law_check probes when it loads the law (PROBE_STEPS), inside a run.
RAISING = '''
from vibrofric.friction_law import Bounds, Parameter

PARAMETERS = {"k_t": Parameter(80e6, "N/m", low=0.0, low_open=True),
              "mu": Parameter(0.1, "", low=0.0)}
STATE_SIZE = 1
INITIAL_STATE = (0.0,)
ORDER = 1


def update(slip_x, slip_y, free_x, free_y, normal_force, area_share, state, params, dt):
    state[0] += 1.0
    if state[0] >= 1000.0:
        raise ValueError("the thousandth call")
    return 0.0, 0.0


def stored_energy(state, params, area_share):
    return 0.0


def bounds(p, dt):
    return Bounds(stiffness=p.k_t, max_stiffness=p.k_t, friction_coefficient=p.mu,
                  max_friction_coefficient=p.mu, departure=1.0)


def steady_sliding_force(p, normal_force, v):
    return p.mu * normal_force
'''


def short(law: str, scene: str = "coupled"):
    """A shipped scene with ``law``, stepped for 0.02 s (20,000 steps)."""
    return scene_module.load(ROOT / "scenes" / f"{scene}.toml").with_values(
        {"contact.law": law, "time.method": "transient", "time.T": 0.02,
         "vibration.t_on": 0.005, "time.average_cycles": 4})


def assert_same_to_rounding(a: np.ndarray, b: np.ndarray) -> None:
    """The same series, or differing at rounding level: each column within 1e-12 of its
    largest value. (The law compiled apart or linked into the loop, where LLVM may
    inline it and fastmath's "contract" fuse its multiplies and adds with the loop's:
    jenkins.py on the coupled scene, 20,000 steps, differs by at most 1.3e-14; a wrong
    call, an argument out of place or another law, at order one.)"""
    assert a.shape == b.shape
    scale = np.max(np.abs(b), axis=0)
    assert np.all(np.abs(a - b) <= 1e-12 * scale)


def new_law(tmp_path, example: str = "jenkins.py") -> Path:
    """An example law under a source no earlier run has compiled (a fingerprint of its own)."""
    path = tmp_path / f"new_{example}"
    path.write_text((LAWS / example).read_text() + f"# {uuid.uuid4().hex}\n")
    return path


@pytest.mark.parametrize("example", ["jenkins.py", "maxwell_slip.py"])
def test_through_its_pointer_a_law_gives_its_specialized_loops_answer(example, monkeypatch):
    """The coupled stepper, oblique vibration (both phases of the update), the law called
    through its pointer and linked into the loop: the same series to rounding level
    (maxwell_slip.py's to the bit, jenkins.py's within 1.3e-14: docs/first-answer.md)."""
    monkeypatch.setenv("VIBROFRIC_SPECIALIZE", "now")
    scene = short(str(LAWS / example))
    with specialize.pointer_route():
        through_pointer = run_coupled(scene)
    linked = run_coupled(scene)
    assert_same_to_rounding(through_pointer.table(), linked.table())
    assert np.ptp(linked.F_y) > 0.0        # the transverse phase ran


def test_a_law_raising_through_its_pointer_is_blamed_on_the_law(tmp_path):
    """numba's C wrapper cannot hand the law's exception to the loop: it is collected
    and raised after the loop's call, as the linked loops' would be (a LawError)."""
    law = tmp_path / "counting.py"
    law.write_text(RAISING)
    with specialize.pointer_route(), pytest.raises(LawError, match="raised ValueError: "
                                                                   "the thousandth call"):
        run_coupled(short(str(law)))


def test_a_new_laws_first_run_goes_through_its_pointer_and_is_specialized_after(
        tmp_path, monkeypatch):
    """A law numba has never compiled: its first run takes the loop compiled for every law
    and lists the specialized loop for after the run; compiled then (as the background
    process does), the specialized loop is in numba's cache for the next process, and
    gives the same series, to rounding level."""
    monkeypatch.setenv("VIBROFRIC_SPECIALIZE", "later")
    pending = []
    monkeypatch.setattr(specialize_later, "_pending", pending)
    law = new_law(tmp_path)
    scene = short(str(law))
    first = run_coupled(scene)
    assert [(module, name, Path(law_name)) for module, name, law_name, _ in pending] == [
        ("vibrofric.analytic.coupled", "coupled_loop", law)]
    sig = pending[0][3]

    def on_disk():
        """Whether a new process would load the specialized loop (a dispatcher of its own,
        nothing in memory)."""
        fresh = specialize.LawKernel(coupled_loop.py_func, coupled_loop.options)
        return not specialize.will_compile(fresh.for_law(scene.friction.law), sig)

    assert not on_disk()
    specialize_later.compile_listed(list(pending))
    pending.clear()                         # nothing left to start at exit
    assert on_disk()
    assert np.array_equal(run_coupled(scene).table(), first.table())   # this process: the
    monkeypatch.setenv("VIBROFRIC_SPECIALIZE", "now")                  # pointer kept
    assert_same_to_rounding(run_coupled(scene).table(), first.table())  # specialized


def test_a_sweep_runs_a_users_law_specialized(monkeypatch):
    """Every sweep the same code: its points compile (or load) the specialized loops first."""
    monkeypatch.delenv("VIBROFRIC_SPECIALIZE", raising=False)
    assert specialize.specialize_when() == "later"
    assert specialize.specialized_first(specialize.specialize_when)() == "now"
    assert specialize.specialize_when() == "later"
    for sweep in (study.run_sweep, in_memory.sweep):
        assert sweep.__wrapped__ is not None


def test_an_unknown_specialize_setting_is_refused_naming_it(monkeypatch):
    monkeypatch.setenv("VIBROFRIC_SPECIALIZE", "sometimes")
    with pytest.raises(ValueError, match="VIBROFRIC_SPECIALIZE"):
        specialize.specialize_when()


def test_the_warm_up_runs_every_shipped_scene():
    """make setup's warm-up names each scene the package ships (scenes/*.toml), so that a
    shipped scene's first run or sweep after set-up compiles nothing."""
    shipped = sorted(path.stem for path in (ROOT / "scenes").glob("*.toml"))
    assert shipped and sorted(warm.SHIPPED) == shipped
    assert all((warm.SCENE_FILES / f"{name}.toml").is_file() for name in warm.SHIPPED)


@pytest.mark.slow
def test_the_reduced_fe_loop_through_its_pointer_gives_the_specialized_answer(monkeypatch):
    """The reduced FE loop with its contact iteration (the law called at every contact
    node, friction sub-step and iterate), stepped: through the law's pointer and
    specialized, the same series to within 1e-9 of the largest force and of the
    largest displacement. (The contact iteration stops at 1e-6 of F_N / k_t, so a
    last-digit difference may end it at another iterate: measured 3e-12 of F_x's
    largest value over 1500 vibrated steps, identical over Fig 7's 0.3 s:
    benchmarks/pointer_route.py. A longitudinal scene's F_y and y are rounding
    noise themselves, hence the scales of all forces and all displacements.)"""
    pytest.importorskip("dolfinx")
    from vibrofric.fem import run_fe

    monkeypatch.setenv("VIBROFRIC_SPECIALIZE", "now")
    scene = short(str(LAWS / "jenkins.py"), "longitudinal").with_values(
        {"fem.integrator": "reduced", "time.dt": 1e-5, "fem.output_every": 0})
    with specialize.pointer_route():
        through_pointer = run_fe(scene).series.table()
    linked = run_fe(scene).series.table()
    assert through_pointer.shape == linked.shape
    for kind in ([1, 2, 3, 8], [4, 5, 6, 7]):     # F_d, F_x, F_y, F_n; x, y, x_b, y_b
        scale = np.max(np.abs(linked[:, kind]))
        assert np.max(np.abs(through_pointer[:, kind] - linked[:, kind])) <= 1e-9 * scale
