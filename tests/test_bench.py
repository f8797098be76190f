"""vibrofric bench: its references, errors, fitted exponents and report, on a small plan."""

import math

import pytest

from vibrofric import bench
from vibrofric.bench import fits
from vibrofric.cli import main

pytest.importorskip("dolfinx")

# The Fig 7 scene shortened to 0.2 s (F_dv over the cycles nearest one drive
# period from 0.14 s), the tiny mesh: seconds, not minutes.
SMALL = bench.Plan(
    T=0.2,
    analytic_dts=(4e-6, 2e-6, 1e-6),
    analytic_reference_dt=1e-8,
    fe_cases=(("explicit", "tiny", 2e-6), ("reduced", "tiny", 1e-5), ("reduced", "tiny", 2e-5)),
    fe_reference=("explicit", "tiny", 1e-6),
    dofs_cases=(("reduced", (("tiny", 1e-5), ("2x2x2", 1e-5), ("2x3x3", 1e-5))),),
    dofs_T=0.01,
    time_cases=(("reduced", "tiny", 1e-5, (0.01, 0.02, 0.04)),),
    laws=(("Dahl, i = 2", "dahl", {"dahl_exponent": 2.0}),),
    law_dt=2e-6,
    law_fe=("reduced", "tiny", 1e-5),
    breakdown_cases=(("explicit", "tiny", 2e-6), ("reduced", "tiny", 1e-5)),
    mesh_study=("reduced", 1e-5, ("tiny", "2x2x2", "2x3x3")),
)


def test_fitted_exponent_recovers_a_power_law():
    x = [10.0, 100.0, 1000.0]
    assert fits.fitted_exponent(x, [3.0 * v ** 1.5 for v in x]) == pytest.approx(1.5, abs=1e-12)


@pytest.fixture(scope="module")
def small():
    return bench.measure(SMALL, progress=lambda text: None)


def test_errors_are_against_each_models_own_reference(small):
    rows = {(m.method, m.setting): m for m in small["rows"]}
    # The paper update's error is first order in dt (its Euler step,
    # docs/model.md): halving dt must halve it, within 1.5-2.5x (the higher
    # orders of a 1e-2-sized error). The exact update's smaller error changes
    # sign with dt (the split's error against the update's): it must shrink.
    def errors(update):
        return [abs(rows[(f"analytic {update}", f"dt = {dt:g}")].error) for dt in SMALL.analytic_dts]
    paper, exact = errors("paper"), errors("exact")
    assert 1.5 < paper[0] / paper[1] < 2.5 and 1.5 < paper[1] / paper[2] < 2.5
    assert exact[0] > exact[1] > exact[2] and exact[2] < paper[2] / 10
    # FE rows are compared with the FE reference, and separately with the analytic one.
    reference = small["fe_reference"].ratio
    for m in small["rows"]:
        if m.method.startswith("FE"):
            assert m.error == pytest.approx((m.ratio - reference) / reference, rel=1e-12)
            assert m.vs_analytic == pytest.approx(
                (m.ratio - small["analytic_reference"]) / small["analytic_reference"], rel=1e-12)
            assert m.loop_s > 0 and m.setup_s > 0 and m.wall_s >= m.loop_s + m.setup_s * 0.99


def test_growth_is_fitted_on_the_measured_points(small):
    for axis, integrator, points, x, y, exponent in small["growth"]:
        assert len(points) == 3 and all(p.loop_s > 0 for p in points)
        assert exponent == pytest.approx(fits.fitted_exponent(x, y), rel=1e-12)
        assert math.isfinite(exponent)
    # Along simulated time every point runs all its steps (no early stop), so the
    # fitted loop times are those of 1000, 2000 and 4000 steps. (Those loops take
    # milliseconds: their times, and so the exponent, are left to the bench.)
    time_axis = [g for g in small["growth"] if g[0] == "simulated time"][0]
    _, _, dt, simulated = SMALL.time_cases[0]
    assert [p.steps for p in time_axis[2]] == [round(T / dt) for T in simulated]


def test_the_report_names_every_method_and_the_plot_is_written(small, tmp_path):
    table = bench.markdown(small)
    for method in ("analytic paper", "analytic exact", "FE explicit", "FE reduced"):
        assert f"| {method} |" in table
    assert table.count("| DOFs | reduced |") == 1 and "| simulated time | reduced |" in table
    bench.plot(small, tmp_path / "bench.png")
    assert (tmp_path / "bench.png").stat().st_size > 10_000


def test_bench_command_writes_its_report(small, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(bench, "measure", lambda plan, progress: small)
    out = tmp_path / "bench"
    assert main(["bench", "--quick", "--out", str(out)]) == 0
    assert {p.name for p in out.iterdir()} == {".vibrofric", "bench.md", "bench.png"}
    assert (out / "bench.md").read_text() in capsys.readouterr().out


def test_a_law_row_is_against_its_own_reference(small):
    """The law row's stepper runs that law (another answer than Dahl's i = 1), its error
    is against its own reference, and the FE run's against the same reference."""
    (row,) = small["laws"]
    dahl = next(m for m in small["rows"] if m.method == "analytic exact" and m.setting == "dt = 2e-06")
    assert abs(row.analytic.ratio - dahl.ratio) > 1e-3
    assert row.analytic.error == pytest.approx((row.analytic.ratio - row.reference) / row.reference,
                                               rel=1e-12)
    # first order in dt, as the Dahl rows: 2e-6 s errs by ~1e-3 of F_dv/F_d0 at most
    assert 0.0 < abs(row.analytic.error) < 1e-2
    assert row.fe.vs_analytic == pytest.approx((row.fe.ratio - row.reference) / row.reference,
                                               rel=1e-12)
    assert "| Dahl, i = 2 |" in bench.markdown(small)


def test_step_breakdown_parts_add_up_to_the_measured_step(small):
    """Each integrator's parts (bench.step_breakdown) and "the rest" sum to the step the
    run measured (to rounding), and the timed parts took time."""
    for b in small["breakdowns"]:
        assert sum(part.seconds for part in b.parts) == pytest.approx(b.step_s, rel=1e-12)
        timed = b.parts[:-1]
        assert all(part.seconds > 0.0 for part in timed)
        assert b.parts[-1].name.startswith("rest")
    explicit, reduced = small["breakdowns"]
    assert [p.name for p in explicit.parts[:2]] == ["product with K", "DOF vectors"]
    assert reduced.parts[0].name == "solve with A"
    assert "| **whole step** |" in bench.markdown(small)


def test_richardson_recovers_a_power_law_on_unequal_refinements():
    """f = f0 + C h^p on element sizes that do not halve: f0 and p to the bisection's
    precision (1e-9 relative is far above its 2^-100); differences of changing sign
    (outside the asymptotic range) give nan rather than a number."""
    h = [13e-3, 7.5e-3, 5e-3, 3.8e-3]
    f0, p, uncertainty = fits.richardson(h, [0.14 + 5.0 * x ** 1.3 for x in h])
    assert f0 == pytest.approx(0.14, rel=1e-9) and p == pytest.approx(1.3, rel=1e-9)
    assert uncertainty == pytest.approx(1.25 * 5.0 * h[-1] ** 1.3, rel=1e-6)
    assert all(math.isnan(v) for v in fits.richardson([4, 2, 1], [1.0, 1.2, 1.1]))


def test_mesh_study_reports_each_level_against_the_extrapolation(small):
    study = small["mesh"]
    assert [run.setting.split(",")[0] for run in study.runs] == ["tiny", "2x2x2", "2x3x3"]
    assert study.sizes[0] > study.sizes[1] > study.sizes[2]
    assert "Mesh study" in bench.markdown(small)


def test_the_fe_study_row_runs_the_command_as_typed_and_counts_the_orbits(monkeypatch, tmp_path):
    """periodic_vs_transient.fe_study runs the vibrofric command of this environment
    (a one-point warm-up, then the 125-point grid) for each method and counts from
    its results.csv the points answered by their orbit; the report's table says so."""
    import subprocess
    from pathlib import Path

    from vibrofric.bench import periodic_vs_transient as pvt

    calls = []

    def fake_run(argv, check, capture_output):
        calls.append(argv)
        out = Path(argv[argv.index("--out") + 1])
        stepped = "time.method=transient" in argv
        rows = ["fe.F_dv_over_F_d0" + ("" if stepped else ",fe.periodic.method")]
        rows += ["0.5" + ("" if stepped else f",{m}") for m in ("periodic", "transient", "periodic")]
        (out / "results.csv").write_text("\n".join(rows) + "\n")
        return subprocess.CompletedProcess(argv, 0)

    monkeypatch.setattr(pvt.subprocess, "run", fake_run)
    result = pvt.fe_study(workers=2)
    assert [argv[0] for argv in calls] == [str(Path(pvt.sys.executable).parent / "vibrofric")] * 4
    assert [("vibration.k_v=2,3,4,6,20" in argv, "time.method=transient" in argv)
            for argv in calls] == [(False, False), (True, False), (False, True), (True, True)]
    assert result["periodic"][2] == 2 and result["transient"][2] == 0
    assert "| points answered by their orbit | 0 | 2 |" in pvt.study_markdown(result)
