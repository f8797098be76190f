"""The FE loops as compiled for an Intel core: no gather instructions.

Where a loop reads through an index array (x[columns[p]], z[indices[p]]) and
the compiler may reorder its sums, LLVM vectorizes it with gather
instructions when it targets Intel cores (not AMD's: its cost model there
says they are slow). Intel's microcode mitigation of Gather Data Sampling
(2023) makes gathers several times slower: the product with K of the
explicit loop, so compiled, ran 5x slower on an Intel Xeon than here. The
loops are written so that no gather is emitted (linalg.py), and the product
with K runs its block rows as four-lane multiply-adds (simd.py).

The loops' parts compiled once for every law (the step's forces, its linear
response, q_{n+1}) are checked beside them. The check compiles the loops for "skylake" (Intel, AVX2: instructions this
x86-64 machine runs too, so the runs that compile them can execute) in a
fresh process with its own numba cache, and reads their assembly.
"""

import json
import platform
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import child_environment

pytest.importorskip("dolfinx")

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = """
import json
from vibrofric import scene as scenes
from vibrofric.fem import run_fe
from vibrofric.fem.model import linalg
from vibrofric.fem.integrators.explicit import explicit_steps, step_forces
from vibrofric.fem.integrators.generalized_alpha import free_response
from vibrofric.fem.integrators.implicit import implicit_steps, new_displacements

base = scenes.load("scenes/longitudinal.toml", ["fem.mesh=tiny", "vibration.t_on=0.0005",
                   "time.T=0.002", "time.average_cycles=2", "fem.output_every=0"])
for integrator, dt in (("explicit", 1e-6), ("implicit", 1e-5), ("reduced", 1e-5)):
    run_fe(base.with_values({"fem.integrator": integrator, "time.dt": dt}))
law = base.friction.law
loops = {"explicit_steps": explicit_steps.for_law(law), "implicit_steps": implicit_steps.for_law(law),
         "step_forces": step_forces, "free_response": free_response,
         "new_displacements": new_displacements,
         "_bsr_apply": linalg._bsr_apply, "_lu_solve": linalg._lu_solve}
counts = {}
for name, dispatcher in loops.items():
    assembly = "".join(dispatcher.inspect_asm().values())
    fma4 = sum("vfmadd" in line and "ymm" in line for line in assembly.splitlines())
    counts[name] = [assembly.count("vgather"), len(assembly), fma4]
print(json.dumps(counts))
"""


def _runs_avx2() -> bool:
    import llvmlite.binding as llvm

    llvm.initialize_native_target()
    return "+avx2" in llvm.get_host_cpu_features().flatten()


@pytest.mark.slow
@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="x86-64 only")
def test_loops_compiled_for_intel_have_no_gathers(tmp_path):
    if not _runs_avx2():
        pytest.skip("this machine cannot run AVX2 code")
    env = child_environment(NUMBA_CPU_NAME="skylake", NUMBA_CACHE_DIR=str(tmp_path))
    result = subprocess.run([sys.executable, "-c", SCRIPT], cwd=ROOT, env=env,
                            capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    counts = json.loads(result.stdout.strip().splitlines()[-1])
    for name, (gathers, size, _) in counts.items():
        assert size > 1000, f"{name}: no assembly compiled"
        assert gathers == 0, f"{name}: {gathers} gather instructions for an Intel target"
    # the product's block rows as four-lane multiply-adds (fem/model/simd.py): three a block
    assert counts["_bsr_apply"][2] >= 3, "the product with K is not four lanes wide"
