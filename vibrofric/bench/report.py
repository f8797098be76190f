"""The bench's report: Markdown tables of what measure() returned, and the plot of wall
time against error."""

from . import machine, periodic_vs_transient
from .fits import relative
from .measuring import MeshStudy
from .plans import GROWTH


def markdown(result: dict) -> str:
    """The bench as Markdown: speed against error, then the cost growth."""
    plan, fe_ref = result["plan"], result["fe_reference"]
    lines = [
        f"Fig 7 scene (longitudinal, k_v = 6, {plan.T:g} s simulated), one core.",
        f"Analytic reference: the exact update at dt = {plan.analytic_reference_dt:g} s, "
        f"F_dv/F_d0 = {result['analytic_reference']:.5f}. FE reference: {fe_ref.method[3:]}, "
        f"{fe_ref.setting} s ({fe_ref.dofs} DOFs, {fe_ref.wall_s:.3g} s wall), "
        f"F_dv/F_d0 = {fe_ref.ratio:.5f}, {fe_ref.vs_analytic:+.2%} from the analytic reference.",
        "",
        "| method | setting | DOFs | wall s | set-up s | F_dv/F_d0 | error vs own reference "
        "| FE vs analytic |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for m in result["rows"]:
        fe = m.dofs > 0
        lines.append(f"| {m.method} | {m.setting} | {m.dofs if fe else '-'} | {m.wall_s:.3g} "
                     f"| {f'{m.setup_s:.2g}' if fe else '-'} | {m.ratio:.5f} | {m.error:+.2e} "
                     f"| {f'{m.vs_analytic:+.2%}' if fe else '-'} |")
    lines += ["",
              f"Cost growth: the time loop's wall time on a short run (vibration from "
              f"{GROWTH['vibration.t_on'] * 1e3:g} ms, F_dv over {GROWTH['time.average_cycles']} "
              f"cycles; {plan.dofs_T:g} s simulated against DOFs), set-up aside.",
              "",
              "| cost against | integrator | points (size: loop s, set-up s) | fitted exponent |",
              "|---|---|---|---|"]
    for axis, integrator, points, x, y, exponent in result["growth"]:
        pairs = ", ".join(f"{size:g}: {p.loop_s:.3g}, {p.setup_s:.2g}"
                          for size, p in zip(x, points))
        lines.append(f"| {axis} | {integrator} | {pairs} | {exponent:.2f} |")
    if result["laws"]:
        lines += ["",
                  f"Friction laws on the same scene: the analytic stepper at dt = "
                  f"{plan.law_dt:g} s against its own reference at dt = "
                  f"{plan.analytic_reference_dt:g} s"
                  + (f"; FE {plan.law_fe[0]}, {plan.law_fe[1]} mesh, dt = {plan.law_fe[2]:g} s, "
                     "against the same reference" if plan.law_fe else "") + ".",
                  "",
                  "| law | reference F_dv/F_d0 | analytic wall s | analytic error "
                  "| FE wall s | FE F_dv/F_d0 | FE vs analytic |",
                  "|---|---|---|---|---|---|---|"]
        for row in result["laws"]:
            fe = row.fe
            fe_cells = (f"{fe.wall_s:.3g} | {fe.ratio:.5f} | {fe.vs_analytic:+.2%}" if fe
                        else "- | - | -")
            lines.append(f"| {row.label} | {row.reference:.5f} | {row.analytic.wall_s:.3g} "
                         f"| {row.analytic.error:+.2e} | {fe_cells} |")
    if result.get("mesh"):
        lines += [""] + mesh_markdown(result["mesh"])
    if result.get("breakdowns"):
        lines += [""] + breakdown_markdown(result["breakdowns"])
    if result.get("periodic"):
        lines += [""] + periodic_vs_transient.markdown(result["periodic"])
    return "\n".join(lines) + "\n"


def mesh_markdown(study: MeshStudy) -> list:
    """The mesh study as Markdown lines: each level against the mesh-converged value."""
    f0, p, uncertainty = study.converged
    lines = [f"Mesh study: FE {study.integrator} at dt = {study.dt:g} s on successively finer "
             f"meshes. Richardson extrapolation of the last three: mesh-converged F_dv/F_d0 = "
             f"{f0:.5f} +- {uncertainty:.1e}, observed order {p:.2f} in the element size.",
             "",
             "| mesh | element size mm | DOFs | set-up s | loop s | F_dv/F_d0 "
             "| error vs mesh-converged |",
             "|---|---|---|---|---|---|---|"]
    for run, h in zip(study.runs, study.sizes):
        level = run.setting.split(",")[0]
        lines.append(f"| {level} | {h * 1e3:.2f} | {run.dofs} | {run.setup_s:.2g} "
                     f"| {run.loop_s:.3g} | {run.ratio:.5f} | {relative(run.ratio, f0):+.2e} |")
    return lines


def breakdown_markdown(breakdowns) -> list:
    """The step breakdowns as Markdown lines: a table of parts, then each step's fraction."""
    lines = [f"A step in parts, on {machine.cpu_name()} (one core): this machine's multiply-add "
             f"rate {machine.multiply_add_rate() / 1e9:.1f} G/s (operands from L1) and bandwidth "
             f"{machine.bandwidth(32_000) / 1e9:.0f} / {machine.bandwidth(400_000) / 1e9:.0f} / "
             f"{machine.bandwidth(4_000_000) / 1e9:.0f} / {machine.bandwidth(256_000_000) / 1e9:.0f}"
             " GB/s (32 KB / 400 KB / 4 MB / 256 MB working sets). Each part's bound is "
             "max(bytes / bandwidth, multiply-adds / rate); the friction law and the rest have "
             "none (bench/step_breakdown.py).",
             "",
             "| integrator | setting | part | us a step | multiply-adds | KB | bound us "
             "| bound / time |",
             "|---|---|---|---|---|---|---|---|"]
    for b in breakdowns:
        for part in b.parts:
            bounded = part.bound > 0.0
            lines.append(
                f"| {b.integrator} | {b.setting} | {part.name} | {part.seconds * 1e6:.2f} "
                f"| {f'{part.multiply_adds:,.0f}' if bounded else '-'} "
                f"| {f'{part.nbytes / 1e3:,.0f}' if bounded else '-'} "
                f"| {f'{part.bound * 1e6:.2f}' if bounded else '-'} "
                f"| {f'{part.bound / part.seconds:.0%}' if bounded else '-'} |")
        lines.append(f"| {b.integrator} | {b.setting} | **whole step** | "
                     f"**{b.step_s * 1e6:.2f}** | | | {b.bound * 1e6:.2f} "
                     f"| **{b.bound / b.step_s:.0%}** |")
    return lines


def plot(result: dict, path) -> None:
    """Wall time against error, log-log, one line per method."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for method in dict.fromkeys(m.method for m in result["rows"]):
        points = sorted((m.wall_s, abs(m.error)) for m in result["rows"]
                        if m.method == method and m.error != 0.0 and "medium" not in m.setting)
        if points:
            ax.loglog(*zip(*points), "o-", ms=4, label=method)
    ax.set(xlabel="wall time, one core (s)",
           ylabel="|error| of F_dv/F_d0 against its own reference",
           title=f"speed against error: Fig 7 scene, {result['plan'].T:g} s simulated")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
