"""Loops compiled per friction law: an edited law never runs stale, a law found by module
name, and the compiled versions kept on disk bounded."""

import os
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest
from llvmlite.binding import Linkage

from vibrofric.friction_law import load_law, specialize

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "laws" / "maxwell_slip.py"


def run_analytic(scene: Path, out: Path) -> str:
    """F_dv/F_d0 of ``vibrofric analytic`` in a fresh process (numba's disk cache only)."""
    done = subprocess.run([sys.executable, "-m", "vibrofric.cli", "analytic", str(scene),
                           "--set", "time.T=0.2", "--out", str(out), "--json"],
                          capture_output=True, text=True, check=True, cwd=ROOT,
                          env={**os.environ, "VIBROFRIC_SPECIALIZE": "now"})  # the law's own loops
    return done.stdout.split('"F_dv_over_F_d0": ')[1].split(",")[0]


def test_an_edited_law_is_compiled_anew_never_run_stale(tmp_path):
    """Run a user's law, edit it, run again in a new process: the second run uses the
    edited law (a different answer), not the first run's cached loop."""
    law = tmp_path / "my_law.py"
    law.write_text(EXAMPLE.read_text())
    scene = tmp_path / "scene.toml"
    scene.write_text((ROOT / "examples" / "laws" / "maxwell_slip.toml").read_text()
                     .replace('"maxwell_slip.py"', '"my_law.py"'))
    first = run_analytic(scene, tmp_path / "first")
    again = run_analytic(scene, tmp_path / "again")
    law.write_text(EXAMPLE.read_text().replace("ELEMENTS = 4", "ELEMENTS = 2"))
    edited = run_analytic(scene, tmp_path / "edited")
    assert first == again          # cached or not, the same law gives the same answer
    assert edited != first         # the edit is in effect


def test_a_law_is_found_by_its_module_name(tmp_path, monkeypatch):
    package = tmp_path / "lawpack"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "slip.py").write_text(EXAMPLE.read_text())
    monkeypatch.syspath_prepend(str(tmp_path))
    law = load_law("lawpack.slip")
    assert law.module.__name__ == "lawpack.slip" and law.state_size == 8


def test_only_the_most_recent_compiled_versions_stay_on_disk(tmp_path):
    prefix = "coupled.coupled_loop__"
    for age, fingerprint in enumerate(f"{k:016x}" for k in range(12)):
        for suffix in ("-41.py311.nbi", "-41.py311.1.nbc"):
            path = tmp_path / f"{prefix}{fingerprint}{suffix}"
            path.write_text("")
            os.utime(path, (1e9 - age, 1e9 - age))   # fingerprint 0 the newest
    other = tmp_path / "coupled.record_row-30.py311.nbi"
    other.write_text("")
    dispatcher = types.SimpleNamespace(_cache=types.SimpleNamespace(_cache_path=str(tmp_path)))
    specialize._prune(dispatcher, prefix)
    kept = {path.name[len(prefix):][:16] for path in tmp_path.glob(prefix + "*")}
    assert kept == {f"{k:016x}" for k in range(specialize.KEPT_VERSIONS)}
    assert other.exists()


def test_a_signal_while_numba_compiles_ends_the_wait_at_once():
    """numba compiles in LLVM's C code, which calls back into Python through ctypes;
    a KeyboardInterrupt raised in such a callback is swallowed (printed as ignored),
    so Ctrl-C or SIGTERM during a new law's compile was lost. The stand-in below
    compiles by such a callback, which signals the process and runs on for 3 s:
    waited for from another thread, the compile is cut short at once."""
    import ctypes
    import signal
    import time

    from vibrofric import parallel

    class CompilingThroughCallback:
        __name__ = "stand_in"

        def compile(self, sig):
            def from_compiled_code():
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(3.0)

            ctypes.CFUNCTYPE(None)(from_compiled_code)()

    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt), parallel.interruptible():
        specialize._compile_interruptibly(CompilingThroughCallback(), ())
    # The wait polls every 0.05 s; 1 s leaves room for a loaded machine and is still
    # well short of the 3 s the swallowed interrupt took before.
    assert time.monotonic() - start < 1.0


@specialize.law_kernel(error_model="numpy")
def _friction_sum(states, params, slip):
    """A law kernel that calls the law (a loop: too large for LLVM to inline twice)."""
    total = 0.0
    for c in range(states.shape[0]):
        f_x, f_y = law_update(slip, 0.0, 0.0, 0.0, 1.0, 1.0,  # noqa: F821 (the law's)
                              states[c], params, 1e-6)
        total += f_x - f_y
    return total


@specialize.law_kernel(error_model="numpy")
def _two_sums(states, params):
    """A law kernel that calls another, twice."""
    return _friction_sum(states, params, 1e-9) + _friction_sum(states, params, -2e-9)


def test_a_law_kernel_calls_only_its_own_copies_of_what_it_calls(tmp_path):
    """numba links a called function into the caller as a copy under the callee's own
    name, which the loader may bind to the callee's separately compiled code instead
    (when that is loaded: in the process that compiled the caller), so the caller's
    bits depended on how its callees came (self_contained_law_kernels). Every linked
    copy in a law kernel must carry a name of that kernel's own, not shared with the
    callee's code or another kernel's copies."""
    law_file = tmp_path / "my_law.py"
    law_file.write_text(EXAMPLE.read_text() + f"# {tmp_path.name}: not compiled before\n")
    law = load_law(str(law_file))
    states = law.initial_state(3)
    params = np.array([80e6, 0.1])
    caller = _two_sums.for_law(law)
    caller(states, params)

    def linked(dispatcher):
        """The names of the functions linked into the dispatcher's one compiled version."""
        module = dispatcher.overloads[dispatcher.signatures[0]].library._final_module
        return {f.name for f in module.functions
                if not f.is_declaration and f.linkage == Linkage.linkonce_odr}

    in_caller = linked(caller)
    in_callee = linked(_friction_sum.for_law(law))
    # the callee is kept as a call (not inlined away), so its copy is there to check
    assert any("_friction_sum__" in name for name in in_caller), in_caller
    suffixes = {name.rpartition(".in.")[2] for name in in_caller}
    assert len(suffixes) == 1 and all(".in." in name for name in in_caller), in_caller
    assert not in_caller & in_callee
