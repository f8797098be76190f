"""One FE run of a scene beside the analytic stepper, written into a directory.

The work of ``vibrofric run`` and of every point of ``vibrofric sweep --fe``:
both run it on a staging directory (output.staged) and add their own summary
and plots; ``vibrofric run`` hands its runs to the plot process (run_beside)
before it writes their files (write_beside), so that both happen at once.
"""

from dataclasses import dataclass

from . import output
from .core.errors import Refusal
from .core.series import TimeSeries, written
from .scene import check_fe_scene, refused

# The analytic stepper beside an FE run runs the scene as it is, at its own time.dt:
# one scene has one analytic answer, whichever command (analytic, run, sweep) runs it.
# Its error is first order in dt (core.law_limits), so beside an FE run at a coarse
# step (the reduced integrator at 1e-5 s: -0.65% on Fig 7) the relative difference
# holds the stepper's own error; core.law_limits.slip_resolved is the stepper at a
# step that resolves the slip, the reference the FE model is validated against.


@dataclass
class FEBesideAnalytic:
    """What fe_beside_analytic() ran and wrote.

    document         the JSON of ``vibrofric run`` less "out": {"fe", "analytic", "rel_error"}
    fe_info          FEResult.info, with "vtk" the ParaView series relative to the directory
    fe               the FEResult (series, fields)
    analytic_series  the analytic stepper's TimeSeries (the scene at its own time.dt)
    """

    document: dict
    fe_info: dict
    fe: object
    analytic_series: TimeSeries


def relative_error(fe: float | None, analytic: float | None) -> float | None:
    """|fe - analytic| / analytic on F_dv/F_d0; None where there is no ratio to compare."""
    if fe is None or not analytic:
        return None
    return abs(fe - analytic) / analytic


def error_keys(fe, scene) -> dict:
    """The FE summary's error keys (the interface's): error_estimate (absolute, on
    F_dv/F_d0: the time step's, fem/step_error.py, plus the mesh's where it was
    estimated; None where the step's was not), error_order, dt_used, dt_asked,
    error_note (how it was made, or "not estimated: " why and how to ask for it),
    mesh_error_estimate and mesh_error_note (fem/simulate.py mesh_error), error_wall_time_s
    (the wall time of the runs the estimates took), and, as the analytic summary's
    (analytic/accuracy.py), accuracy (time.accuracy) and dt_for_accuracy: the step
    that brings the step's share of the error within what the mesh's leaves of it
    (the error falling as dt^p, p observed or the integrators' order), None where it
    is met already or the mesh's error alone exceeds it."""
    from .fem.step_error import FORMAL_ORDER

    keys = fe.step_error.as_dict()
    mesh = fe.mesh_error.get("mesh_error_estimate")
    accuracy = scene.time.accuracy
    step_for = None
    if keys["error_estimate"] is not None and (mesh or 0.0) < accuracy:
        step_for = fe.step_error.step_for(accuracy - (mesh or 0.0), FORMAL_ORDER)
    if keys["error_estimate"] is not None and mesh is not None:
        keys["error_estimate"] += mesh
        keys["error_note"] += "; plus the mesh's error (mesh_error_estimate)"
    return {**keys, **fe.mesh_error, "error_wall_time_s": fe.info["error_wall_time_s"],
            "accuracy": accuracy, "dt_for_accuracy": step_for}


def fe_beside_analytic(scene, directory, comm=None, progress=None,
                       full_series: bool = False, start=None, inputs: bool = True) -> FEBesideAnalytic:
    """Run the scene's FE model and the analytic stepper beside it (run_beside), and
    write their files into ``directory`` (write_beside): scene.toml, timeseries.csv
    (FE), analytic_timeseries.csv and, if fem.output_every > 0, paraview/.
    ``inputs``: scene.toml with the files it reads copied beside it (write_beside).

    Raises SceneError (the model's refusal, naming the key) or NumericalError, leaving whatever it wrote
    by then for the caller's output.staged() to drop.
    """
    done = run_beside(scene, directory, comm, progress, start)
    write_beside(directory, scene, done, full_series, inputs)
    return done


# The FE run's keys the summary's fe block takes as they are (fem/simulate.py): the
# normal force over the steady cycle (the interface's keys) and, with fem.energy, the
# energy balance's closure over it (fem/outputs/energy.py energy_closure).
FE_NORMAL_KEYS = ("contact_loss_fraction", "normal_force_mean", "normal_force_min",
                  "normal_force_max")
FE_ENERGY_KEYS = ("energy_closure", "energy_base_work", "energy_friction_dissipation",
                  "energy_damping_dissipation")


def run_beside(scene, directory, comm=None, progress=None, start=None) -> FEBesideAnalytic:
    """Run the scene's FE model (on ``comm``, default MPI.COMM_SELF; its ParaView
    frames into ``directory``/paraview if fem.output_every > 0) and the analytic
    stepper (at the scene's time.dt, as ``vibrofric analytic``); write nothing else.
    ``progress``, if given, follows the FE time loop or shooting (fem.run_fe);
    ``start``, a neighbour's FE orbit state (time.method periodic or auto: fem.run_fe);
    without it, the FE shooting starts from the analytic stepper's F_dv (run first).

    Raises SceneError (the model's refusal, naming the key) or NumericalError.
    """
    from .analytic.solve import solve
    from .analytic.summary import summarize, summarize_orbit
    from .fem import run_fe
    from .fem.outputs.normal_swing import rule_note, settled

    check_fe_scene(scene)
    analytic_series, analytic = solve(scene)
    try:     # a shooting without a neighbour's orbit starts from the lumped model's F_dv
        fe = run_fe(scene, comm=comm, vtk_dir=directory / "paraview", progress=progress,
                    start=start, drive_force=analytic["F_dv"])
    except Refusal as refusal:
        raise refused(refusal) from refusal
    info = fe.info
    answered = info.get("periodic", {}).get("method") == "periodic"
    if answered:    # the steady cycle: its mean, no breakaway, settled (summarize_orbit)
        summary = {**summarize_orbit(fe.orbit, scene), "wall_time_s": info["wall_time_s"]}
    else:
        summary = summarize(fe.series, scene, info["wall_time_s"])
        if "periodic" in info:
            summary["periodic"] = info["periodic"]
    fe_summary = {**summary,
                  "dofs": info["dofs"], "contact_nodes": info["contact_nodes"],
                  "contact_area": info["contact_area"], "peak_pressure": info["peak_pressure"],
                  "nodes_in_contact": info["nodes_in_contact"],
                  **{key: info[key] for key in ("contact_area_range", "peak_pressure_range",
                                                "nodes_in_contact_range") if key in info},
                  "integrator": info["integrator"], "integrator_choice": info["integrator_choice"],
                  "steps": info["steps"], "stopped_early": info["stopped_early"],
                  "stop_time_s": info["stop_time_s"], "saving": info["saving"],
                  "normal_force": info["F_n_kind"], **error_keys(fe, scene),
                  "normal_force_node_swing": info["F_n_node_swing"],
                  "normal_force_rule": info["normal_force_rule"],
                  "normal_force_rule_note": rule_note(info["F_n_node_swing"],
                                                      info["normal_force_rule"]),
                  **{key: info[key] for key in FE_NORMAL_KEYS + FE_ENERGY_KEYS if key in info}}
    if not answered and not settled(info["F_n_kind"], info["F_n_forced_fraction"]):
        # its average holds part of a transient, or of an irregular bouncing
        fe_summary["settled"] = False
    document = {"fe": fe_summary, "analytic": analytic,
                "rel_error": relative_error(fe_summary["F_dv_over_F_d0"], analytic["F_dv_over_F_d0"])}
    fe_info = {**fe.info, "vtk": "paraview/block.pvd" if fe.info["frames"] else None}
    return FEBesideAnalytic(document, fe_info, fe, analytic_series)


def write_beside(directory, scene, done: FEBesideAnalytic, full_series: bool = False,
                 inputs: bool = True) -> None:
    """Write run_beside's ``done`` into ``directory``: scene.toml (with ``inputs``, the
    files it reads copied beside it: output.write_scene_and_inputs; without, named where
    they are, as a sweep's point names them), timeseries.csv (FE) and
    analytic_timeseries.csv, with the rows core.series.written() names, or with
    ``full_series`` every kept row."""
    if inputs:
        output.write_scene_and_inputs(directory, scene)
    else:
        output.write_scene(directory, scene)
    output.write_timeseries(directory, written(done.fe.series, scene, full_series))
    output.write_timeseries(directory, written(done.analytic_series, scene, full_series),
                            "analytic_timeseries.csv")
