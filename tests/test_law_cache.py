"""A user's law's compiled loops are cached in the user's cache directory, not in the
installed package (friction_law/law_cache.py)."""

import json
import shutil
import subprocess
import sys

from conftest import ROOT, child_environment

# In a process of its own: numba's dispatchers are made once per law and process.
COMPILE_ONE_STEP = """
import json, sys
import numpy as np
from vibrofric.friction_law import ContactLaw, contact_step, load_law
from vibrofric.friction_law.law import _contact_step
loaded = load_law(sys.argv[1])
law = ContactLaw(loaded, loaded.values({"k_t": 8e7}), 55.0)
nodes = 2
state = loaded.initial_state(nodes)
contact_step(law, state, np.full((nodes, 2), 1e-9), np.zeros((nodes, 2)), np.full(nodes, 27.5),
             np.full(nodes, 0.5), 1e-6)
print(json.dumps({"fingerprint": loaded.fingerprint,
                  "path": str(_contact_step.for_law(loaded)._cache._cache_path)}))
"""


def test_a_user_laws_loops_are_cached_under_the_users_cache_directory(tmp_path):
    """The loop compiled for a copy of examples/laws/maxwell_slip.py: its numba index and
    code under $VIBROFRIC_CACHE/numba, and nothing with the law's fingerprint in the
    package's __pycache__ directories."""
    law = tmp_path / "my_law.py"
    shutil.copy(ROOT / "examples" / "laws" / "maxwell_slip.py", law)
    cache = tmp_path / "cache"
    environment = {**child_environment(), "VIBROFRIC_CACHE": str(cache)}
    environment.pop("NUMBA_CACHE_DIR", None)
    done = subprocess.run([sys.executable, "-c", COMPILE_ONE_STEP, str(law)], env=environment,
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.splitlines()[-1])
    fingerprint = report["fingerprint"]
    assert report["path"].startswith(str(cache / "numba"))
    cached = [p.name for p in (cache / "numba").rglob(f"*{fingerprint}*")]
    assert any(name.endswith(".nbi") for name in cached)
    assert any(name.endswith(".nbc") for name in cached)
    in_package = [p for p in (ROOT / "vibrofric").rglob(f"__pycache__/*{fingerprint}*")]
    assert in_package == []
