"""Simulate a scene with the FE model: ``run_fe(scene, comm=None, vtk_dir=None) -> FEResult``:
stepped through time.T, or (time.method periodic / auto) answered by its steady cycle."""

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core.base_table import moves_along_z
from ..core.series import (RecordPlan, TimeSeries, averaging_steps, check_stepped_window,
                           full_resolution_steps)
from ..core.shooting import periodic_block
from ..core.errors import NumericalError, Refusal
from ..core.step_error import not_estimated
from ..meshes import level_counts
from . import step_error
from .integrators import periodic, registry
from .integrators.cycle_map import FECycleMap
from .model.fe_model import build_model, cached_levels
from .model.linalg import one_blas_thread
from .outputs.contact_patch import patch, patch_range
from .outputs.energy import energy_closure
from .outputs.normal_swing import judge, node_swing, normal_force_keys
from .outputs.paraview import FrameWriter, node_fields
from .outputs.recording import COLUMNS, scene_extra_columns


@dataclass
class FEResult:
    """One FE run.

    series  core.series.TimeSeries: t, F_d, F_x, F_y (summed nodal friction
            force, paper sign), x, y (attachment nodes' mean displacement since
            the preload), x_b, y_b, and extra["F_n"] (summed normal reaction),
            with fem.energy also extra[recording.ENERGY]; the rows the analytic
            stepper keeps up to the step the run ended at (early steady
            state: outputs/steady.py), so summarize() applies as is
    info    what the run was and cost (run_info), and its contact patch at the end
            (outputs/contact_patch.patch: nodes_in_contact, contact_area,
            peak_pressure; a steady cycle's answer adds their *_range over the cycle)
    fields  the node fields at the last step, as in the ParaView frames
            (paraview.FIELDS, arrays over the nodes) plus "coordinates" (nodes, 3),
            "contact_nodes" (indices) and "t" (the step's time, s)
    orbit   with time.method "periodic" or "auto": the shooting's core.shooting.Orbit
            (whether or not it answered: info["periodic"]["method"] says), else None
    step_error  core.step_error.StepError of F_dv/F_d0 (its estimate None where none
            was made: its note says why)
    mesh_error  {"mesh_error_estimate": float or None, "mesh_error_note": str}
    """

    series: TimeSeries
    info: dict = field(default_factory=dict)
    fields: dict = field(default_factory=dict, repr=False)
    orbit: object = None
    step_error: object = None
    mesh_error: dict = field(default_factory=dict)


def _communicator(comm):
    """The run's communicator: None stands for MPI.COMM_SELF, started only when DOLFINx
    is used (dolfinx_adapter.communicator)."""
    if comm is None:
        return None
    if comm.size > 1:
        raise ValueError(f"an FE run is serial: got a communicator of {comm.size} processes; "
                         "run batches as many single-process runs (MPI.COMM_SELF) side by side")
    return comm


@dataclass(frozen=True)
class Clock:
    """A run's wall times, s: the set-up (the model, the integrator's factorization or
    reduction), the time loop alone, and the whole run."""

    setup_s: float
    loop_s: float
    wall_s: float


def run_fe(scene, comm=None, vtk_dir=None, progress=None, start=None,
           drive_force=None) -> FEResult:
    """Run the scene's finite-element model (docs/model.md section 5).

    comm     an MPI communicator of one process (default MPI.COMM_SELF)
    vtk_dir  if given and fem.output_every > 0: write vtk_dir/block.pvd, a frame
             every fem.output_every steps (outputs/paraview.py); a run answered by its
             steady cycle writes periodic.FRAMES_PER_CYCLE + 1 frames of that cycle
    progress if given, called as progress(t_done_s, t_total_s) every few
             thousand steps of the time loop (simulated seconds), and while the
             steady cycle is shot for, as progress(cycles, None) after each base
             cycle (no total: the shooting ends when it converges)
    start    with time.method "periodic" or "auto": a neighbouring point's orbit
             state (FEResult.orbit.z) to shoot from (sweeps: continuation)
    drive_force  with time.method "periodic" or "auto" and no ``start``: the mean
             drive force expected (the lumped model's F_dv), N: the shooting starts
             from steady sliding set back by the drive spring's stretch under it
             instead of under F_d0 (periodic.find_orbit)

    With time.method "periodic" or "auto" (and vibration) the steady cycle is shot
    for first (integrators/periodic.py); where that does not converge or the orbit is not
    stable, the scene is stepped through T as with "transient". info["periodic"]
    (core.shooting.periodic_block) says which answered.

    The answer's time-step error (FEResult.step_error: step_error.py): from a second
    answer at dt/2 where time.error_estimate asks for it; with fem.integrator "auto",
    the step is the one whose estimate meets time.accuracy (step_error.search_step)
    and the integrator the cheapest at the first step tried (registry.choose). The
    mesh's error (FEResult.mesh_error) where the block of another refinement level is
    cached (mesh_error).

    Raises core.errors.Refusal for a scene the model cannot run, before
    the first step, and NumericalError for a run that went wrong (NaN, a
    diverging asperity, the normal force blowing up or ringing). The result's
    info is run_info's, with error_wall_time_s: the wall time of the estimates' runs.
    """
    start_time = time.perf_counter()
    comm = _communicator(comm)
    model = build_model(scene, comm)
    if scene.fem.integrator == "auto":     # the answers at the steps tried count as the estimate's
        run_scene, chosen = _auto_step(scene, model, drive_force)
        search_time = time.perf_counter() - start_time
        result = _run(run_scene, model, vtk_dir, progress, chosen.start, drive_force,
                      time.perf_counter())
        result.info["integrator_requested"] = "auto"
        result.info["integrator_choice"] = chosen.text
        result.step_error = chosen.error
        estimates_begin = time.perf_counter() - search_time
    else:
        result = _run(scene, model, vtk_dir, progress, start, drive_force, start_time)
        estimates_begin = time.perf_counter()
        result.step_error = _step_error(scene, model, result, drive_force)
    result.mesh_error = mesh_error(scene, result, comm)
    end = time.perf_counter()
    result.info["error_wall_time_s"] = end - estimates_begin
    result.info["wall_time_s"] = end - start_time
    return result


def shoots(scene) -> bool:
    """Whether the steady cycle is shot for (integrators/periodic.py) before any stepping:
    time.method "periodic" or "auto", a vibrated scene, a base motion that repeats (a
    measured motion that ends has no periodic orbit: "auto" steps it, "periodic" is
    refused by the scene's checks)."""
    return (scene.time.method != "transient" and scene.vibrated
            and scene.vibration.repeats)


def _run(scene, model, vtk_dir, progress, start, drive_force, start_time) -> FEResult:
    """The answer at the scene's own integrator and step (run_fe without its estimates)."""
    prepare = registry.select(scene)
    orbit = None
    if shoots(scene):
        shot_scene, steps = periodic.periodic_scene(scene)
        integrator = prepare(shot_scene, model)
        phi = FECycleMap(integrator, integrator.model, steps)    # the compiled step loaded
        if progress is not None:
            phi.on_cycle = lambda cycles: progress(cycles, None)
        setup_time = time.perf_counter() - start_time
        # BLAS on one thread, as in the time loop (time_loop.TimeLoop.integrate): the
        # cycles are its steps, with their ~100 x 100 products (linalg.one_blas_thread)
        with one_blas_thread():
            orbit = periodic.find_orbit(phi, start, drive_force)
            if orbit.converged and orbit.stable:
                return _steady_cycle(scene, shot_scene, model, integrator, orbit, phi, vtk_dir,
                                     start_time, setup_time)
        check_stepped_window(scene, "no stable periodic orbit, so the scene is stepped through time.T: its ")
        if shot_scene is not scene:
            integrator = prepare(scene, model)
    else:
        integrator = prepare(scene, model)
    setup_time = time.perf_counter() - start_time

    writer = _frame_writer(scene, model, vtk_dir)
    try:
        run = _integrate(scene, integrator, writer, progress)
    finally:
        if writer is not None:
            writer.close()
    series = TimeSeries.from_table(run.table, scene_extra_columns(scene))
    swing = judge(series.extra["F_n"][-averaging_steps(scene):], scene.time.dt,
                  scene.vibration.f, scene.contact.F_N, model.beta,
                  moves_along_z(scene.vibration))
    stats = {**run.stats, "F_n_node_swing": node_swing(run.node_normals)}
    clock = Clock(setup_time, run.stats["loop_time_s"], time.perf_counter() - start_time)
    info = {**run_info(scene, model, integrator, stats, swing, writer, clock),
            **patch(model.contact_area, run.state.normal)}
    window = averaging_steps(scene)
    info.update(normal_force_keys(series.extra["F_n"][-window:], run.node_normals))
    info.update(energy_closure(series, scene, window))
    if orbit is not None:
        info["periodic"] = periodic_block(orbit, scene)
    return FEResult(series=series, info=info, fields=last_fields(model, run.state), orbit=orbit)


def _answer_at(scene, model, dt, start, periodic_answer: bool, drive_force=None):
    """step_error.Answer: F_dv/F_d0 of ``scene`` at the step ``dt``, by its integrator
    on ``model``: with ``periodic_answer`` the steady cycle (shot from the orbit state
    ``start``, else from steady sliding under ``drive_force``; no Floquet multipliers:
    the orbit at the scene's own step was judged), else stepped through T."""
    at = scene.with_values({"time.dt": dt, "fem.output_every": 0})
    F_d0 = at.friction.steady_sliding_force(at.contact.F_N, at.drive.v_d)
    try:
        if periodic_answer:
            shot, steps = periodic.periodic_scene(at)
            shot_run = registry.select(shot)(shot, model)
            phi = FECycleMap(shot_run, shot_run.model, steps)
            with one_blas_thread():
                orbit = periodic.find_orbit(phi, start, drive_force, stability=False)
            if not orbit.converged:
                return step_error.Answer(shot.time.dt, None, None,
                                         f"no steady cycle at {shot.time.dt:.4g} s: {orbit.reason}")
            F_dv, dt, start = float(np.mean(orbit.cycle[:, 1])), shot.time.dt, orbit.z
        else:
            run = _integrate(at, registry.select(at)(at, model), None, None)
            F_d = TimeSeries.from_table(run.table, scene_extra_columns(at)).F_d
            F_dv, start = float(np.mean(F_d[-averaging_steps(at):])), None
    except (NumericalError, Refusal) as trouble:
        return step_error.Answer(dt, None, None, f"at {dt:.4g} s: {trouble}")
    if not (F_d0 > 0.0 and math.isfinite(F_dv)):
        return step_error.Answer(dt, None, None, f"F_dv/F_d0 is not a number at {dt:.4g} s")
    return step_error.Answer(dt, F_dv / F_d0, start)


def answer_ratio(result: FEResult, scene) -> float | None:
    """The answer's F_dv/F_d0, as the summary computes it (analytic/summary.py)."""
    F_d0 = scene.friction.steady_sliding_force(scene.contact.F_N, scene.drive.v_d)
    if result.info.get("periodic", {}).get("method") == "periodic":
        F_dv = float(np.mean(result.orbit.cycle[:, 1]))
    else:
        F_dv = float(np.mean(result.series.F_d[-averaging_steps(scene):]))
    return F_dv / F_d0 if F_d0 > 0.0 and math.isfinite(F_dv) else None


def _step_error(scene, model, result: FEResult, drive_force):
    """The answer's StepError from a second answer at dt/2 (step_error.halved_estimate),
    where time.error_estimate asks for it (step_error.reason_not_to)."""
    answered = result.info.get("periodic", {}).get("method") == "periodic"
    dt_used = result.info["dt"]
    why = step_error.reason_not_to(scene, answered)
    if why is not None:
        return not_estimated(dt_used, scene.time.dt, why)
    ratio = answer_ratio(result, scene)
    if ratio is None:
        return not_estimated(dt_used, scene.time.dt, "F_dv/F_d0 is not a number (F_d0 = 0)")
    first = step_error.Answer(dt_used, ratio, result.orbit.z if answered else None)
    return step_error.halved_estimate(
        first, lambda dt, start: _answer_at(scene, model, dt, start, answered, drive_force),
        scene.time.dt)


def _auto_step(scene, model, drive_force):
    """fem.integrator = "auto": (the scene to answer, at the integrator and step picked,
    and step_error.StepChoice). The integrator is the cheapest at the first step tried
    (registry.choose), the step the one step_error.search_step finds for it."""
    periodic_answer = shoots(scene)
    dt0 = step_error.first_step(scene)
    for halvings in range(step_error.MAX_HALVINGS + 1):   # a stiff contact: no integrator at 25
        if periodic_answer:                                # a cycle (the contact iteration)
            dt0 = periodic.periodic_scene(scene.with_values({"time.dt": dt0}))[0].time.dt
        try:
            picked = registry.choose(scene.with_values({"time.dt": dt0}), model)
            break
        except Refusal:
            if halvings == step_error.MAX_HALVINGS:
                raise
            dt0 /= 2.0
    named = scene.with_values({"fem.integrator": picked.name})
    chosen = step_error.search_step(
        named, lambda dt, start: _answer_at(named, model, dt, start, periodic_answer,
                                            drive_force), dt0)
    chosen = dataclasses.replace(chosen, text=f"{picked.choice}; {chosen.text}")
    return named.with_values({"time.dt": chosen.dt}), chosen


NO_MESH_PARTNER = "tiny"


def mesh_error(scene, result: FEResult, comm) -> dict:
    """The mesh's error of F_dv/F_d0, from the block of another refinement level where
    the model cache holds one (fe_model.cached_levels): the same integrator at the
    same step on it, |F - F_other|. Another level is run where time.error_estimate is
    true (the nearest finer one cached, else the nearest coarser), or "auto" and the
    step's error was estimated (the nearest coarser one: cheaper than the answer; its
    difference bounds the answer's error where the meshes converge monotonically)."""
    key = {"mesh_error_estimate": None}
    mesh = scene.fem.mesh
    if scene.time.error_estimate is False:
        return {**key, "mesh_error_note": "not estimated: time.error_estimate = false"}
    # the one-element "tiny" block (the tests' smallest) has no contact patch to speak
    # of: its difference from any other says nothing of their error
    cached = [level for level in cached_levels(scene) if level != NO_MESH_PARTNER]
    size = math.prod(level_counts(mesh))
    finer = sorted((l for l in cached if math.prod(level_counts(l)) > size),
                   key=lambda l: math.prod(level_counts(l)))
    coarser = sorted((l for l in cached if math.prod(level_counts(l)) < size),
                     key=lambda l: -math.prod(level_counts(l)))
    estimated = result.step_error is not None and result.step_error.estimate is not None
    if scene.time.error_estimate is True:
        other = (finer + coarser or [None])[0]
    else:
        other = coarser[0] if coarser and estimated else None
    if other is None:
        why = ("no block of another refinement level is cached" if not cached else
               f"the cached levels ({', '.join(cached)}) are not run under time.error_estimate "
               '= "auto" (a coarser one is, beside an estimated step error)')
        return {**key, "mesh_error_note": f"not estimated: {why}; a run with another fem.mesh "
                                          "caches its block (fem/model/model_cache.py)"}
    ratio = answer_ratio(result, scene)
    other_scene = scene.with_values({"fem.mesh": other, "fem.integrator": result.info["integrator"],
                                     "time.dt": result.info["dt"], "time.error_estimate": False,
                                     "fem.output_every": 0})
    try:
        other_ratio = answer_ratio(run_fe(other_scene, comm), other_scene)
    except (NumericalError, Refusal) as trouble:
        return {**key, "mesh_error_note": f"not estimated: the {other} mesh's run failed: {trouble}"}
    if ratio is None or other_ratio is None:
        return {**key, "mesh_error_note": "not estimated: F_dv/F_d0 is not a number"}
    side = "finer" if other in finer else "coarser"
    return {"mesh_error_estimate": abs(ratio - other_ratio),
            "mesh_error_note": f"|F({mesh}) - F({other})|, the {side} {other} mesh's block cached "
                               f"(the same integrator and step)"}


def _steady_cycle(scene, shot_scene, model, integrator, orbit, phi, vtk_dir, start_time,
                  setup_time) -> FEResult:
    """The FEResult of a run answered by its steady cycle (``orbit``, shot on
    ``shot_scene``: the scene at a step that puts a whole number in a cycle): the
    series the cycle repeated over the last two averaging windows (at least the
    plotted cycles) ending at time.T, the ParaView frames of one cycle, the fields at
    its end. Its steps are the cycles the shooting integrated; its loop time the
    shooting's."""
    cycles = max(1, math.ceil(full_resolution_steps(shot_scene) / orbit.steps))
    series = TimeSeries.from_table(periodic.steady_table(orbit, shot_scene, cycles),
                                   scene_extra_columns(scene))
    writer = _frame_writer(scene, model, vtk_dir)
    try:
        last = periodic.cycle_frames(phi, orbit, scene.time.T, writer)
    finally:
        if writer is not None:
            writer.close()
    # the nodes' normal forces over the cycle cycle_frames integrated: the orbit's
    node_normals = integrator.full_normals(phi.recorder.node_normals(phi.i0 + phi.steps,
                                                                     phi.steps))
    f_n = orbit.cycle[:, COLUMNS.index("F_n")]
    steps = orbit.cycles_integrated * orbit.steps
    stats = {"steps": steps, "steps_planned": scene.steps, "stopped_early": False,
             "stop_time_s": None, "saving": 1.0 - steps / scene.steps,
             "steady_tolerance": scene.time.steady_tolerance,
             "steady_cycles": scene.time.steady_cycles or scene.averaged_cycles,
             "steady_change": None,
             "F_n_min": float(f_n.min()), "F_n_max": float(f_n.max()),
             "F_n_min_after_t_on": float(f_n.min()), "F_n_max_after_t_on": float(f_n.max()),
             "F_n_node_swing": node_swing(node_normals)}
    swing = judge(series.extra["F_n"][-averaging_steps(shot_scene):], shot_scene.time.dt,
                  scene.vibration.f, scene.contact.F_N, model.beta,
                  moves_along_z(scene.vibration))
    clock = Clock(setup_time, orbit.solver_time_s, time.perf_counter() - start_time)
    info = {**run_info(shot_scene, model, integrator, stats, swing, writer, clock),
            **patch(model.contact_area, last.normal),
            **patch_range(model.contact_area, node_normals)}
    info.update(normal_force_keys(f_n, node_normals))
    info["periodic"] = periodic_block(orbit, scene)
    return FEResult(series=series, info=info, fields=last_fields(model, last), orbit=orbit)


def _frame_writer(scene, model, vtk_dir):
    """The ParaView frame series the run writes, or None (no vtk_dir, or no frames asked for)."""
    if vtk_dir is None or scene.fem.output_every <= 0:
        return None
    return FrameWriter(model, vtk_dir)


def _integrate(scene, integrator, writer, progress):
    """The integrator's time loop over the steps the analytic stepper's RecordPlan keeps,
    ``progress`` told in simulated seconds."""
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))

    def steps_done(step, steps):
        progress(step * scene.time.dt, steps * scene.time.dt)

    return integrator.integrate(plan, frame=writer, every=scene.fem.output_every,
                                progress=None if progress is None else steps_done)


def run_info(scene, model, integrator, stats: dict, swing, writer, clock: Clock) -> dict:
    """What the run was and cost (FEResult.info), in this order:

    model_info's keys; the steps (steps run, steps_planned, stopped_early,
    stop_time_s: None if it ran to time.T, saving: the fraction of the planned
    steps not run, steady_tolerance, steady_cycles, steady_change: outputs/steady.py);
    normal_force_info's keys; frames and vtk (the .pvd path or None);
    setup_time_s, loop_time_s, wall_time_s; what the integrator's set-up reports
    (integrators/implicit.py ImplicitRun.info, integrators/reduction.py ReducedRun.info) and its
    iterations_* statistics.
    """
    return {
        **model_info(scene, model, integrator),
        **{key: stats[key] for key in STEP_KEYS},
        **normal_force_info(scene, model, stats, swing),
        "frames": writer.frames if writer is not None else 0,
        "vtk": str(writer.path) if writer is not None else None,
        "setup_time_s": clock.setup_s,
        "loop_time_s": clock.loop_s,
        "wall_time_s": clock.wall_s,
        **integrator.info,
        **{key: value for key, value in stats.items() if key.startswith("iterations_")},
    }


# The integrators' statistics of the steps run (time_loop, outputs/steady.py), as they report them.
STEP_KEYS = ("steps", "steps_planned", "stopped_early", "stop_time_s", "saving",
             "steady_tolerance", "steady_cycles", "steady_change")


def model_info(scene, model, integrator) -> dict:
    """The model that ran: mesh, integrator (the one that ran), integrator_requested
    (fem.integrator), integrator_choice (for "auto": what it picked and why; else None),
    nodes, dofs, elements, contact_nodes, attach, attach_nodes, density (kg/m^3),
    block_mass (kg), top_pressure (Pa), penalty (N/m), damping (beta, s), omega_max
    (rad/s), dt, dt_stable (s; the explicit integrator's limit)."""
    disc = model.disc
    return {
        "mesh": scene.fem.mesh,
        "integrator": integrator.name,
        "integrator_requested": scene.fem.integrator,
        "integrator_choice": integrator.choice,
        "nodes": disc.nodes,
        "dofs": disc.dofs,
        "elements": int(disc.cells.shape[0]),
        "contact_nodes": int(model.contact_nodes.size),
        "attach": scene.drive.attach,
        "attach_nodes": int(model.attach_nodes.size),
        "density": model.density,
        "block_mass": model.block_mass,
        "top_pressure": model.pressure,
        "penalty": model.penalty,
        "damping": model.beta,
        "omega_max": model.omega_max,
        "dt": scene.time.dt,
        "dt_stable": model.dt_stable,
    }


def normal_force_info(scene, model, stats: dict, swing) -> dict:
    """The summed normal force: F_n_static (N, the preload's reaction), F_n_min /
    F_n_max (every step), F_n_min_after_t_on / F_n_max_after_t_on (every step from
    vibration.t_on; None without vibration), and the averaging window's as
    normal_swing.judge found it: F_n_kind ("steady", "rocking", "transient", and with the
    base moving along Z "forced", "bouncing" or "subharmonic"; a ringing run raises),
    F_n_min_window / F_n_max_window, F_n_forced_fraction (the
    share of the window's swing at harmonics of f), F_n_min_window_end /
    F_n_max_window_end / F_n_forced_fraction_end (the window's end),
    F_n_free_frequency_hz (the largest line of the window's swing off the harmonics
    of f; None where steady); and the nodes' normal forces: F_n_node_swing (their
    swing over the window, normal_swing.node_swing) and normal_force_rule (what
    each node's law saw: fem.normal_force)."""
    return {
        "F_n_static": float(model.normal0.sum()),
        "F_n_min": stats["F_n_min"],
        "F_n_max": stats["F_n_max"],
        "F_n_min_after_t_on": stats["F_n_min_after_t_on"] if scene.vibrated else None,
        "F_n_max_after_t_on": stats["F_n_max_after_t_on"] if scene.vibrated else None,
        "F_n_kind": swing.kind,
        "F_n_min_window": swing.low,
        "F_n_max_window": swing.high,
        "F_n_forced_fraction": swing.forced,
        "F_n_min_window_end": swing.end_low,
        "F_n_max_window_end": swing.end_high,
        "F_n_forced_fraction_end": swing.end_forced,
        "F_n_free_frequency_hz": swing.free_frequency_hz,
        "F_n_node_swing": stats["F_n_node_swing"],
        "normal_force_rule": scene.fem.normal_force,
    }


def last_fields(model, state) -> dict:
    """The node fields at the run's last step, as in the ParaView frames (paraview.FIELDS),
    with the nodes' "coordinates", the "contact_nodes" indices and the step's time "t" (s)."""
    fields = node_fields(model, state)
    fields["coordinates"] = model.disc.coordinates
    fields["contact_nodes"] = model.contact_nodes
    fields["t"] = state.t
    return fields
