"""A first answer without hidden work: the model cache (disk_cache.py, fem/model/model_cache.py)
and the compile announcement and lock (friction_law/specialize.py)."""

import json
import subprocess
import sys
import uuid

import numpy as np
import pytest

from vibrofric import disk_cache
from vibrofric.friction_law import specialize

from conftest import ROOT, child_environment

LAW = ROOT / "examples" / "laws" / "maxwell_slip.py"


# --- disk_cache: checked, atomic entries --------------------------------------------------------

def test_an_entry_reads_back_bit_for_bit(tmp_path):
    arrays = {"a": np.random.default_rng(1).standard_normal((7, 3)), "n": np.arange(5),
              "x": np.float64(0.1)}
    disk_cache.write_arrays(tmp_path / "e.npz", arrays)
    back = disk_cache.read_arrays(tmp_path / "e.npz")
    assert set(back) == set(arrays)
    for name, value in arrays.items():
        assert back[name].dtype == np.asarray(value).dtype
        assert np.array_equal(back[name], value)
    assert [p.name for p in tmp_path.iterdir()] == ["e.npz"]  # no temporary file left


@pytest.mark.parametrize("damage", ["flip", "truncate", "empty", "garbage"])
def test_a_damaged_entry_is_removed_and_rebuilt(tmp_path, damage):
    path = tmp_path / "e.npz"
    builds = []

    def build():
        builds.append(1)
        return {"a": np.arange(100.0)}

    disk_cache.cached_arrays(path, build)
    data = bytearray(path.read_bytes())
    if damage == "flip":
        data[-10] ^= 0x01
    elif damage == "truncate":
        data = data[:len(data) // 2]
    elif damage == "empty":
        data = b""
    else:
        data = b"not an entry at all"
    path.write_bytes(bytes(data))
    assert disk_cache.read_arrays(path) is None and not path.exists()
    arrays, hit = disk_cache.cached_arrays(path, build)
    assert not hit and len(builds) == 2 and np.array_equal(arrays["a"], np.arange(100.0))
    arrays, hit = disk_cache.cached_arrays(path, build)
    assert hit and len(builds) == 2


def test_a_cache_that_cannot_be_written_is_passed_by(tmp_path):
    (tmp_path / "a file").write_text("")
    path = tmp_path / "a file" / "models" / "e.npz"   # under a file: no directory there
    for _ in range(2):
        arrays, hit = disk_cache.cached_arrays(path, lambda: {"a": np.arange(3.0)})
        assert not hit and np.array_equal(arrays["a"], np.arange(3.0))


def test_prune_keeps_the_most_recently_used(tmp_path):
    import os

    for k in range(5):
        disk_cache.write_arrays(tmp_path / f"block-{k}.npz", {"k": np.array(k)})
        os.utime(tmp_path / f"block-{k}.npz", (1000 + k, 1000 + k))
    os.utime(tmp_path / "block-0.npz", (2000, 2000))     # used last
    disk_cache.write_arrays(tmp_path / "other.npz", {"k": np.array(9)})
    disk_cache.prune(tmp_path, "block-*.npz", 2)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["block-0.npz", "block-4.npz",
                                                           "other.npz"]


@pytest.mark.parametrize("damage", ["flip", "truncate", "foreign"])
def test_a_mapped_array_file_is_checked(tmp_path, damage):
    """A large array kept as a plain file is mapped only where its bytes are the ones
    its SHA-256 names (held by a checked entry); else it is removed."""
    array = np.random.default_rng(2).standard_normal((40, 7))
    path = tmp_path / "basis.npy"
    disk_cache.write_array_file(path, array)
    digest = disk_cache.array_digest(array)
    mapped = disk_cache.mapped_array(path, digest, array.shape)
    assert type(mapped) is np.ndarray and np.array_equal(mapped, array)
    assert not mapped.flags.writeable and [p.name for p in tmp_path.iterdir()] == ["basis.npy"]
    del mapped
    if damage == "foreign":
        disk_cache.write_array_file(path, array[:, :6])      # another shape
    else:
        data = bytearray(path.read_bytes())
        if damage == "flip":
            data[-8] ^= 0x01
        else:
            data = data[:len(data) // 2]
        path.write_bytes(bytes(data))
    assert disk_cache.mapped_array(path, digest, array.shape) is None and not path.exists()
    assert disk_cache.mapped_array(path, digest, array.shape) is None   # absent


def test_the_cache_directory_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.delenv("VIBROFRIC_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert disk_cache.cache_root() == tmp_path / "vibrofric"
    monkeypatch.setenv("VIBROFRIC_CACHE", str(tmp_path / "own"))
    assert disk_cache.cache_root() == tmp_path / "own"


# --- the FE model cache -------------------------------------------------------------------------

@pytest.fixture
def model_cache_dir(monkeypatch, tmp_path):
    pytest.importorskip("dolfinx")
    monkeypatch.setenv("VIBROFRIC_CACHE", str(tmp_path))
    monkeypatch.setenv("VIBROFRIC_MODEL_CACHE", "1")
    return tmp_path / "models"


def _short_scene(load_scene, integrator, dt):
    """8 cycles of vibration, stepped (time.method transient)."""
    return load_scene("longitudinal", vibration__t_on=0.0005, time__T=0.0025,
                      time__average_cycles=2, time__dt=dt, fem__integrator=integrator,
                      fem__output_every=0, time__method="transient")


def test_a_repeat_run_reads_the_model_from_the_cache(model_cache_dir, load_scene, monkeypatch):
    from mpi4py import MPI

    from vibrofric.fem.integrators import reduction
    from vibrofric.fem.model import fe_model, model_cache

    scene = _short_scene(load_scene, "reduced", 1e-5)
    first = fe_model.build_model(scene, MPI.COMM_SELF)
    reduction.forget()
    first_reduction = reduction.reduced(first, scene.fem.cutoff * scene.vibration.f)
    entries = sorted(p.name.split("-")[0] for p in model_cache_dir.glob("*.npz"))
    assert entries == ["body", "preload", "reduction", "source"]

    def no_assembly(*args, **kwargs):
        raise AssertionError("assembled again despite the cache")

    def no_preload(*args, **kwargs):
        raise AssertionError("preloaded again despite the cache")

    def no_reduction(*args, **kwargs):
        raise AssertionError("reduced again despite the cache")

    monkeypatch.setattr(model_cache, "assemble_body", no_assembly)
    monkeypatch.setattr(fe_model, "static_preload", no_preload)
    monkeypatch.setattr(reduction.Reduction, "__init__", no_reduction)
    reduction.forget()
    second = fe_model.build_model(scene, MPI.COMM_SELF)
    second_reduction = reduction.reduced(second, scene.fem.cutoff * scene.vibration.f)
    for name in ("coordinates", "mass", "cells"):
        assert np.array_equal(getattr(first.disc, name), getattr(second.disc, name))
    K1, K2 = first.disc.stiffness, second.disc.stiffness
    assert (np.array_equal(K1.indptr, K2.indptr) and np.array_equal(K1.indices, K2.indices)
            and np.array_equal(K1.data, K2.data))
    assert np.array_equal(first.u0, second.u0) and first.dt_stable == second.dt_stable
    assert (np.array_equal(first.normal0, second.normal0)
            and np.array_equal(first.in_contact0, second.in_contact0))
    for name in reduction.Reduction.STORED + ("basis",):
        assert np.array_equal(getattr(first_reduction, name), getattr(second_reduction, name))
    reduction.forget()


def test_a_corrupt_model_entry_is_rebuilt(model_cache_dir, load_scene, monkeypatch):
    from mpi4py import MPI

    from vibrofric.fem.model import fe_model, model_cache

    scene = _short_scene(load_scene, "explicit", 1e-6)
    first = fe_model.build_model(scene, MPI.COMM_SELF)
    (entry,) = model_cache_dir.glob("body-*.npz")
    data = bytearray(entry.read_bytes())
    data[len(data) // 2] ^= 0xFF
    entry.write_bytes(bytes(data))
    assembled = []
    assemble = model_cache.assemble_body
    monkeypatch.setattr(model_cache, "assemble_body",
                        lambda *args: assembled.append(1) or assemble(*args))
    again = fe_model.build_model(scene, MPI.COMM_SELF)
    assert assembled                                # assembled anew, not read
    assert np.array_equal(first.disc.stiffness.data, again.disc.stiffness.data)
    assert disk_cache.read_arrays(entry) is not None  # and stored again, whole


def test_the_cached_reduction_reads_its_basis_when_first_asked_for(model_cache_dir,
                                                                   load_scene, monkeypatch):
    """The reduced run's set-up from the cache reads the small arrays only; the basis is
    mapped when a state is first expanded into the whole field, and a damaged or pruned
    basis file is made again, the same bits."""
    from mpi4py import MPI

    from vibrofric.fem.integrators import reduction
    from vibrofric.fem.model import fe_model

    scene = _short_scene(load_scene, "reduced", 1e-5)
    cutoff = scene.fem.cutoff * scene.vibration.f
    model = fe_model.build_model(scene, MPI.COMM_SELF)
    reduction.forget()
    made = reduction.reduced(model, cutoff)
    (basis_file,) = model_cache_dir.glob("basis-*.npy")
    mapped, mapping = [], disk_cache.mapped_array
    monkeypatch.setattr(disk_cache, "mapped_array",
                        lambda *args: mapped.append(1) or mapping(*args))
    reduction.forget()
    read = reduction.reduced(model, cutoff)
    system = read.system()
    q = np.random.default_rng(3).standard_normal(read.size)
    assert not mapped                               # set up without the basis
    assert np.array_equal(system.expand(q), made.basis @ q) and mapped == [1]
    assert np.array_equal(read.basis, made.basis) and mapped == [1]   # mapped once

    data = bytearray(basis_file.read_bytes())
    data[len(data) // 2] ^= 0x01
    basis_file.write_bytes(bytes(data))
    reduction.forget()
    again = reduction.reduced(model, cutoff)
    assert np.array_equal(again.basis, made.basis) and len(mapped) == 2   # made again
    digest = disk_cache.array_digest(made.basis)
    assert mapping(basis_file, digest, made.basis.shape) is not None   # stored again
    basis_file.unlink()
    reduction.forget()
    assert np.array_equal(reduction.reduced(model, cutoff).basis, made.basis)
    reduction.forget()


def test_a_cached_reduced_run_writes_the_same_frames(model_cache_dir, load_scene, tmp_path):
    """A reduced run that builds its reduction and one that reads it from the cache (its
    basis mapped when the frames first need it) give the same series, fields and
    ParaView files, bit for bit."""
    from vibrofric.fem import run_fe
    from vibrofric.fem.integrators import reduction

    scene = _short_scene(load_scene, "reduced", 1e-5).with_values({"fem.output_every": 50})
    reduction.forget()
    built = run_fe(scene, vtk_dir=tmp_path / "built")
    reduction.forget()
    read = run_fe(scene, vtk_dir=tmp_path / "read")
    assert read.info["integrator"] == "reduced" and built.info["frames"] > 1
    assert np.array_equal(built.series.table(), read.series.table())
    for name, field in built.fields.items():
        assert np.array_equal(field, read.fields[name]), name
    written = sorted(p.name for p in (tmp_path / "built").iterdir())
    assert written == sorted(p.name for p in (tmp_path / "read").iterdir())
    for name in written:
        assert ((tmp_path / "built" / name).read_bytes()
                == (tmp_path / "read" / name).read_bytes()), name
    reduction.forget()


@pytest.mark.parametrize("integrator, dt", [("explicit", 1e-6), ("reduced", 1e-5)])
def test_results_are_bit_identical_with_and_without_the_cache(model_cache_dir, load_scene,
                                                              monkeypatch, integrator, dt):
    from vibrofric.fem import run_fe
    from vibrofric.fem.integrators import reduction

    scene = _short_scene(load_scene, integrator, dt)
    monkeypatch.setenv("VIBROFRIC_MODEL_CACHE", "0")
    reduction.forget()
    without = run_fe(scene)
    assert not model_cache_dir.exists()
    monkeypatch.setenv("VIBROFRIC_MODEL_CACHE", "1")
    reduction.forget()
    run_fe(scene)                    # writes the entries
    reduction.forget()
    cached = run_fe(scene)           # reads them
    assert cached.info["integrator"] == integrator
    assert np.array_equal(without.series.table(), cached.series.table())
    for name, field in without.fields.items():
        assert np.array_equal(field, cached.fields[name]), name
    reduction.forget()


def test_frames_from_a_cached_model_need_no_dolfinx(model_cache_dir, load_scene, tmp_path):
    """A repeat run writes its ParaView frames from the cached model's arrays: the
    same files, byte for byte, with neither DOLFINx, gmsh, MPI nor meshio imported."""
    from vibrofric import output
    from vibrofric.fem import run_fe

    scene = _short_scene(load_scene, "explicit", 1e-6).with_values({"fem.output_every": 1000})
    first = run_fe(scene, vtk_dir=tmp_path / "a")   # builds the model, or reads it
    output.write_scene(tmp_path, scene)
    code = ("import sys; from vibrofric import scene as s; from vibrofric.fem import run_fe; "
            f"run_fe(s.load({str(tmp_path / 'scene.toml')!r}), vtk_dir={str(tmp_path / 'b')!r}); "
            "print(sorted(m for m in ('dolfinx', 'gmsh', 'mpi4py', 'petsc4py', 'meshio') "
            "if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=child_environment(VIBROFRIC_CACHE=str(model_cache_dir.parent)),
                          cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "[]"
    assert first.info["frames"] > 1
    written = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert written == sorted(p.name for p in (tmp_path / "b").iterdir())
    for name in written:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name


# --- compiling: announced, once, never from a damaged cache -------------------------------------

def _new_law(tmp_path, elements: int) -> str:
    """maxwell_slip.py with another element count: a law numba has never compiled, and
    a scene of it (examples/laws/maxwell_slip.toml's) beside it."""
    text = LAW.read_text()
    changed = text.replace("ELEMENTS = 4", f"ELEMENTS = {elements}", 1)
    assert changed != text
    changed += f"# {uuid.uuid4().hex}: a source no earlier test run has compiled\n"
    path = tmp_path / f"slip{elements}.py"
    path.write_text(changed)
    scene = LAW.with_suffix(".toml").read_text().replace('"maxwell_slip.py"', f'"{path.name}"')
    (tmp_path / f"slip{elements}.toml").write_text(scene)
    return str(path)


def _analytic(tmp_path, scene="scenes/longitudinal.toml", numba_cache=None):
    # The loops specialized for the law at its first run (through_pointer.py: the route of
    # a law's first runs, with the default VIBROFRIC_SPECIALIZE=later, tests/test_through_pointer.py)
    env = child_environment(VIBROFRIC_SPECIALIZE="now",
                            **({"NUMBA_CACHE_DIR": str(numba_cache)} if numba_cache else {}))
    done = subprocess.run(
        [sys.executable, "-m", "vibrofric.cli", "analytic", str(scene),
         "--set", "time.T=0.02", "--set", "vibration.t_on=0.005", "--set", "time.average_cycles=4",
         "--out", str(tmp_path / "out"), "--force", "--json"],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done


def test_a_new_law_announces_its_compile_once(tmp_path):
    law = _new_law(tmp_path, 6)
    first = _analytic(tmp_path, law.replace(".py", ".toml"), numba_cache=tmp_path / "numba")
    assert ("vibrofric: compiling the coupled analytic stepper for slip6.py, first run only"
            in first.stderr)
    second = _analytic(tmp_path, law.replace(".py", ".toml"), numba_cache=tmp_path / "numba")
    assert "compiling" not in second.stderr
    assert json.loads(first.stdout)["F_dv"] == json.loads(second.stdout)["F_dv"]


def test_a_warmed_built_in_law_compiles_nothing(tmp_path):
    _analytic(tmp_path)                   # loads or compiles the Dahl stepper
    again = _analytic(tmp_path)
    assert "compiling" not in again.stderr


def test_will_compile_sees_memory_and_disk(tmp_path, monkeypatch):
    from vibrofric import scene as scene_module
    from vibrofric.analytic.coupled import coupled_loop, load_coupled

    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("VIBROFRIC_SPECIALIZE", "now")   # not through the law's pointer
    scene = scene_module.load(ROOT / "scenes" / "longitudinal.toml").with_law(_new_law(tmp_path, 7))
    law = scene.friction.law
    args = (0.5, 1.0, 1.0, False, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 55.0,
            law.initial_state(1)[0], scene.friction.params, 1e-6, 1, 0, 1, 1, 1.0,
            np.zeros(11), np.empty((0, 8)))
    dispatcher = coupled_loop.for_law(law)
    assert specialize.will_compile(dispatcher, args)
    load_coupled(scene)
    assert not specialize.will_compile(dispatcher, args)


def test_a_damaged_numba_cache_entry_is_compiled_anew(tmp_path):
    law = _new_law(tmp_path, 8)
    cache = tmp_path / "numba"
    first = _analytic(tmp_path, law.replace(".py", ".toml"), numba_cache=cache)
    damaged = [path for path in cache.rglob("*coupled_loop__*.nbc")]
    assert damaged
    for path in damaged:
        path.write_bytes(b"\x80\x04garbage, not a pickle")
    again = _analytic(tmp_path, law.replace(".py", ".toml"), numba_cache=cache)
    assert json.loads(again.stdout)["F_dv"] == json.loads(first.stdout)["F_dv"]


# --- honest progress ----------------------------------------------------------------------------

def test_the_loop_reports_its_start_before_any_step(load_scene):
    pytest.importorskip("dolfinx")
    from vibrofric.fem import run_fe

    reports = []
    scene = _short_scene(load_scene, "explicit", 1e-6)
    run_fe(scene, progress=lambda done, total: reports.append(done))
    assert reports[0] == 0.0 and reports.count(0.0) == 1 and reports[-1] > 0.0


def test_the_bar_is_drawn_when_the_loop_starts_and_restarts_its_clock():
    """Nothing before the time loop's first report (set-up, compiling, or a shooting for
    the steady cycle that steps no loop at all); a second start restarts the clock."""
    import argparse
    import time

    from vibrofric import cli

    bar = cli._LoopBar(argparse.Namespace(json=False), "FE", 0.3)
    try:
        assert bar.bar is None
        bar(0.0, 0.3)                 # the time loop starts
        assert bar.bar.n == 0
        bar.bar.start_t -= 100.0      # as if it had run for 100 s
        bar(0.0, 0.3)                 # and starts again
        assert bar.bar.n == 0 and time.time() - bar.bar.start_t < 100.0
        bar(0.1, 0.3)
        bar(30000 * 1e-5, 0.3)        # the last step's time, a rounding past T
        assert bar.bar.n == bar.bar.total == 0.3
    finally:
        bar.close()


def test_a_shooting_shows_its_cycles_without_a_rate_then_a_stepped_fallback_its_bar(capsys):
    """While the steady cycle is shot for (progress(cycles, None)) the bar counts base
    cycles, with no total, rate or time left; a run stepped after it (the shooting
    failed) gets the time loop's bar over simulated seconds."""
    import argparse

    from vibrofric import cli

    bar = cli._LoopBar(argparse.Namespace(json=False), "FE", 0.3)
    try:
        for cycles in range(1, 41):
            bar(cycles, None)
        assert bar.counting_cycles and bar.bar.n == 40 and bar.bar.total is None
        bar.bar.start_t -= 100.0      # shown, as if it had run past CYCLES_SHOWN_AFTER
        bar(41, None)
        bar(0.0, 0.3)                 # the shooting failed: the time loop starts
        assert not bar.counting_cycles and bar.bar.n == 0 and bar.bar.total == 0.3
    finally:
        bar.close()
    shown = capsys.readouterr().err
    assert "41 base cycles shot" in shown and "it/s" not in shown and "cycle/s" not in shown


def test_the_warm_up_keeps_the_compilers_chatter_off_the_terminal():
    """python -m vibrofric.warm's logging (library_logs.quiet_libraries, first thing, as
    in every vibrofric command): a library that logs at INFO (FFCx's basicConfig, then
    setuptools lowering the root logger to INFO and logging each C compiler command
    line, on a first FE model build) is not shown; a warning is."""
    code = ("import logging; from vibrofric.warm import quiet_libraries; quiet_libraries(); "
            "logging.basicConfig(); logging.getLogger().setLevel(logging.INFO); "
            "logging.info('building libffcx_forms'); logging.warning('a warning kept')")
    done = subprocess.run([sys.executable, "-c", code], env=child_environment(), cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "a warning kept" in done.stderr
    assert "libffcx" not in done.stderr and "INFO" not in done.stderr


LAW_FREE_PARTS = ("free_response", "newmark_update", "new_displacements", "base_over_substeps",
                  "commit_contact", "step_forces", "held_attachment", "contact_motion",
                  "next_contact_start", "newton_on_subset")


@pytest.mark.slow
def test_a_new_law_compiles_its_loops_not_their_law_free_parts(tmp_path):
    """The FE steps' parts that do not call the friction law (generalized_alpha,
    implicit.new_displacements, explicit.step_forces ...) are compiled once for all
    laws: a second law's runs add loops to numba's cache, and nothing of theirs."""
    law = _new_law(tmp_path, 9)
    cache = tmp_path / "numba"
    code = ("import sys; from vibrofric import scene as s; from vibrofric.fem import run_fe; "
            "base = s.load('scenes/longitudinal.toml', ['vibration.t_on=0.0005', 'time.T=0.0025', "
            "'time.average_cycles=2', 'fem.output_every=0', 'fem.mesh=tiny']); "
            "base = base if sys.argv[1] == 'dahl' else base.with_law(sys.argv[1]); "
            "[run_fe(base.with_values({'fem.integrator': i, 'time.dt': dt})) "
            "for i, dt in (('explicit', 1e-6), ('reduced', 1e-5))]")

    def compiled(name_part):
        """numba's cache files of the functions named so: each compiled version's .nbc,
        and the index (.nbi) with the time it was last written."""
        return sorted((p.name, p.stat().st_mtime_ns if p.suffix == ".nbi" else 0)
                      for p in cache.rglob(f"*{name_part}*") if p.suffix in (".nbi", ".nbc"))

    for which in ("dahl", law):
        done = subprocess.run([sys.executable, "-c", code, which], cwd=ROOT, timeout=1200,
                              env=child_environment(NUMBA_CACHE_DIR=str(cache),
                                                    VIBROFRIC_SPECIALIZE="now"),
                              capture_output=True, text=True)
        assert done.returncode == 0, done.stderr[-2000:]
        if which == "dahl":
            parts = {name: compiled(f".{name}-") for name in LAW_FREE_PARTS}
            loops = compiled("_steps__")
            assert all(parts.values()), parts
    assert {name: compiled(f".{name}-") for name in LAW_FREE_PARTS} == parts
    assert len(compiled("_steps__")) > len(loops)   # the new law's own loops


@pytest.mark.slow
def test_a_new_law_gives_the_same_bits_compiled_and_loaded_from_the_cache(tmp_path):
    """A new law's implicit and reduced runs, one after the other in one process that
    compiles their loops, then again in a new process that loads them from numba's
    cache: every column the same to the bit. (With the loops' calls bound to whichever
    copy of a called function was loaded first, the implicit run's F_d differed by
    1.5e-12 of itself between the two: specialize.self_contained_law_kernels.)"""
    law = _new_law(tmp_path, 5)
    code = ("import sys, numpy as np; from vibrofric import scene as s; "
            "from vibrofric.fem import run_fe; "
            "base = s.load('scenes/longitudinal.toml', ['vibration.t_on=0.01', 'time.T=0.02', "
            "'time.average_cycles=4', 'fem.output_every=0', 'fem.energy=true', "
            "'time.method=\"transient\"']).with_law(sys.argv[1]); "
            "np.savez(sys.argv[2], **{i: run_fe(base.with_values({'fem.integrator': i, "
            "'time.dt': 1e-5})).series.table() for i in ('implicit', 'reduced')})")
    for name in ("compiled", "loaded"):
        done = subprocess.run([sys.executable, "-c", code, law, str(tmp_path / name)],
                              cwd=ROOT, env=child_environment(VIBROFRIC_SPECIALIZE="now"),
                              capture_output=True, text=True, timeout=1200)
        assert done.returncode == 0, done.stderr[-2000:]
        assert ("compiling" in done.stderr) == (name == "compiled"), done.stderr
    compiled, loaded = np.load(tmp_path / "compiled.npz"), np.load(tmp_path / "loaded.npz")
    for integrator in ("implicit", "reduced"):
        assert np.array_equal(compiled[integrator], loaded[integrator]), integrator
