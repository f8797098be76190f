"""The package as a user installs it: a wheel built from this checkout, installed (not
editable) into a fresh virtual environment, run from a directory outside the checkout.

The shipped scenes are package data (vibrofric/scenes), so load_scene("longitudinal"),
the command's --version and the bench's scenes must work without the repository.
The environment is Debian's Python with its system packages (numpy, numba, DOLFINx,
as ``make setup`` makes .venv); the few dependencies Debian lacks are linked in from
this interpreter's copies. Building, installing and compiling every loop afresh in
the new location make these tests slow.
"""

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import vibrofric

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parent.parent
SYSTEM_PYTHON = Path("/usr/bin/python3")
# Import names of pyproject.toml's dependencies.
DEPENDENCIES = ("numpy", "numba", "scipy", "threadpoolctl", "matplotlib", "tqdm", "tomli_w",
                "pandas")


def run(command, cwd, env=None, timeout=600):
    done = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)
    assert done.returncode == 0, f"{command}: {done.stdout}\n{done.stderr}"
    return done.stdout


def missing(python: Path, names) -> list:
    """The modules of ``names`` that ``python`` cannot import."""
    code = ("import importlib.util, sys; print(' '.join(n for n in sys.argv[1:] "
            "if importlib.util.find_spec(n) is None))")
    return run([str(python), "-c", code, *names], cwd="/").split()


def link_from_here(names, into: Path) -> None:
    """This interpreter's copies of the modules ``names`` (a package's folder, or a
    module's file), linked into ``into``."""
    into.mkdir()
    for name in names:
        spec = importlib.util.find_spec(name)
        source = (Path(spec.submodule_search_locations[0]) if spec.submodule_search_locations
                  else Path(spec.origin))
        (into / source.name).symlink_to(source)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(python, vibrofric command, a working directory outside the checkout, environment)."""
    if not SYSTEM_PYTHON.exists() or sys.version_info[:2] != (3, 11):
        pytest.skip("the installed package is checked on Debian's Python 3.11 (make setup)")
    if missing(SYSTEM_PYTHON, ["numpy", "numba", "dolfinx"]):
        pytest.skip("Debian's python3-dolfinx-real (make setup) is not installed")
    tmp = tmp_path_factory.mktemp("installed")
    # The sources a wheel is built from, copied (the scenes link followed) so that the
    # build leaves nothing in the checkout.
    source = tmp / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, source / name)
    shutil.copytree(ROOT / "vibrofric", source / "vibrofric",
                    ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
         str(source), "-w", str(tmp / "dist")], cwd=tmp)
    wheel, = (tmp / "dist").glob("vibrofric-*.whl")
    assert wheel.name.startswith(f"vibrofric-{vibrofric.__version__}-")   # pyproject's version

    venv = tmp / "venv"
    run([str(SYSTEM_PYTHON), "-m", "venv", "--system-site-packages", str(venv)], cwd=tmp)
    python = venv / "bin" / "python"
    lacking = missing(python, DEPENDENCIES)
    if lacking:
        link_from_here(lacking, tmp / "dependencies")
        site = Path(run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                        cwd=tmp).strip())
        (site / "dependencies.pth").write_text(f"{tmp / 'dependencies'}\n")
    run([str(python), "-m", "pip", "install", "--no-deps", "--no-index", "-q", str(wheel)],
        cwd=tmp)

    work = tmp / "elsewhere"
    work.mkdir()
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    env["NUMBA_CACHE_DIR"] = str(tmp / "numba-cache")
    env["VIBROFRIC_CACHE"] = str(tmp / "cache")
    return python, venv / "bin" / "vibrofric", work, env


def test_the_command_prints_its_version(installed):
    _, command, work, env = installed
    assert run([str(command), "--version"], cwd=work, env=env).strip() == \
        f"vibrofric {vibrofric.__version__}"


def test_the_api_runs_a_shipped_scene_from_the_installed_package(installed):
    """load_scene by name reads the package data; the analytic run answers (Fig 7's scene,
    shortened: F_dv/F_d0 between 0 and 1, vibration lowers the drive force)."""
    python, _, work, env = installed
    code = """
import json, vibrofric as vf
scene = vf.load_scene("longitudinal", **{"time.T": 0.2})
result = vf.run_analytic(scene)
print(json.dumps({"file": vf.__file__, "names": vf.scene_names(),
                  "ratio": result.F_dv_over_F_d0, "rows": len(result.timeseries)}))
"""
    answer = json.loads(run([str(python), "-c", code], cwd=work, env=env).splitlines()[-1])
    assert "site-packages" in answer["file"] and not answer["file"].startswith(str(ROOT))
    assert answer["names"] == ["ball", "coupled", "longitudinal", "pin", "transverse"]
    assert 0.0 < answer["ratio"] < 1.0 and answer["rows"] > 100


def test_the_command_runs_a_shipped_scene_by_name(installed, tmp_path):
    python, command, work, env = installed
    out = tmp_path / "analytic"
    document = json.loads(run([str(command), "analytic", "transverse", "--set", "time.T=0.2",
                               "--json", "--out", str(out)], cwd=work, env=env))
    assert 0.0 < document["F_dv_over_F_d0"] < 1.0 and (out / "summary.json").exists()


def test_the_bench_finds_its_scenes_in_the_installed_package(installed):
    """vibrofric bench's scenes (plans.SCENE, the periodic rows' SCENES) are package data;
    the example law, which lives in the repository's examples/, is left out."""
    python, _, work, env = installed
    code = """
from vibrofric.bench import periodic_vs_transient, plans
scene = plans.base_scene(plans.QUICK)
print(scene.name, sorted(p.name for p in periodic_vs_transient.SCENES.glob("*.toml")),
      [label for label, _, _ in plans.LAWS][-1])
"""
    assert run([str(python), "-c", code], cwd=work, env=env).split("\n")[0] == \
        "longitudinal ['ball.toml', 'coupled.toml', 'longitudinal.toml', 'pin.toml', " \
        "'transverse.toml'] " \
        "LuGre, F_s = 1.2 F_c, v_s = 2 mm/s"


def test_the_bench_command_runs_from_the_installed_package(installed, tmp_path):
    """``vibrofric bench --quick`` end to end (the command, its scene, the FE runs, the
    report), with its plan cut to a few seconds of runs on the one-element mesh."""
    python, _, work, env = installed
    out = tmp_path / "bench"
    code = f"""
import sys
from vibrofric import bench, cli
bench.QUICK = bench.Plan(
    T=0.2, analytic_dts=(4e-6, 2e-6), analytic_reference_dt=1e-7,
    fe_cases=(("reduced", "tiny", 1e-5),), fe_reference=("explicit", "tiny", 2e-6),
    dofs_cases=(("reduced", (("tiny", 1e-5), ("2x2x2", 1e-5))),), dofs_T=0.01,
    time_cases=(("reduced", "tiny", 1e-5, (0.01, 0.02)),))
sys.exit(cli.main(["bench", "--quick", "--out", {str(out)!r}]))
"""
    table = run([str(python), "-c", code], cwd=work, env=env)
    assert "| FE reduced | tiny, dt = 1e-05 |" in table and "| analytic exact |" in table
    assert (out / "bench.md").read_text() in table and (out / "bench.png").stat().st_size > 10_000
