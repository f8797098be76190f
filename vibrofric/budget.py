"""What a run will need, estimated from its scene before any work: memory, disk, time.

A scene whose runs cannot fit on this machine is refused (SceneError naming
the key that makes it so) before anything is built or written, with the
estimate in the message. The estimates are rough upper bounds:

    memory  the kept time series (RecordPlan rows x columns x 8 bytes, held
            about three times over: the loop's buffers, the table, the CSV
            writer), and for FE the block's model, FE_BYTES_PER_DOF a degree
            of freedom (K in three sparse formats, the mass, the preload and
            the reduction's coupling on the coarse to fine meshes)
    disk    the CSV time series (CSV_BYTES_PER_VALUE a value; the rows
            core.series.written() keeps, or all kept rows with --full-series) and
            for FE the ParaView frames (VTK_BYTES_PER_NODE a node and frame)
    time    STEP_SECONDS a step, and FE_STEP_SECONDS_PER_DOF a degree of
            freedom and step: the explicit loop of the coarse mesh; and for FE
            FRICTION_UPDATE_SECONDS per friction-law update of a contact node, of
            which a stiff or fast contact takes many a step (the explicit loop's
            sub-steps, fem.integrators.explicit.explicit_substeps, at most
            fem.model.contact.MAX_SUBSTEPS), and the analytic stepper run beside
            at the scene's time.dt

A sweep's grid is checked as a whole too (check_grid), counted rather than
expanded: the memory its planned points hold, the disk they write, its time.
"""

import copy
import os
import shutil
from pathlib import Path

from .core.series import COLUMNS, RecordPlan, full_resolution_steps, written_rows
from .meshes import level_counts
from .output import existing_ancestor
from .scene import SceneError, check_fe_scene

FE_BYTES_PER_DOF = 4_000
CSV_BYTES_PER_VALUE = 25           # a double's repr and its comma
VTK_BYTES_PER_NODE = 600           # 7 fields, 22 values a node, base64 + headers
STEP_SECONDS = 1e-7                # the analytic stepper: 30-70 ns a step
ESTIMATE_RUNS = 1 + 2 + 4          # a stepped analytic answer and its runs at dt/2 and dt/4, in
                                   # steps of dt (the step error: analytic/accuracy.py)
FE_STEP_SECONDS_PER_DOF = 6e-8     # explicit, coarse mesh: ~40 us for 720 DOFs
FRICTION_UPDATE_SECONDS = 6e-8     # one law update of one node (fem.integrators.step_cost.COST["friction"])
POINT_BYTES = 16_384               # a sweep point without series: scene.toml, summary.json, checks.json
POINT_MEMORY = 8_192               # a sweep's memory a point of its grid: ~2.5 KB planned (its values,
                                   # scene and name: 20,000 longitudinal points measured), its record
                                   # and its scene.toml's text as read back on a resume
PLAN_SECONDS = 1e-3                # making a point (its scene, checked) before any runs: ~0.6 ms measured
POINT_SECONDS = 4e-3               # a sweep point's own work beside its runs (its scene, writing
                                   # and reading back): 3.9 ms measured (docs/performance.md)
WORKER_BYTES = 200 * 2**20         # a pool worker: the interpreter, numpy, numba and the loops,
                                   # 115-139 MiB measured (docs/performance.md), with a margin;
                                   # the FE model's arrays come on top (batch/study.py)
LONGEST_RUN_S = 30 * 86400         # refused beyond: a typo in time.T rather than a study
LONG_RUN_S = 3600                  # announced beyond (long_run_notice): within reach, but long


def _bytes(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if n < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}"
        n /= 1024


def _duration(seconds: float) -> str:
    for unit, size in (("years", 365 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def available_memory() -> int:
    """Bytes of memory this machine can give a new process (MemAvailable)."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def free_disk(directory: Path) -> int:
    """Bytes free on the file system that holds ``directory`` (or its nearest existing parent)."""
    return shutil.disk_usage(existing_ancestor(directory)).free


def fe_dofs(scene) -> int:
    nx, ny, nz = level_counts(scene.fem.mesh)
    return 3 * (nx + 1) * (ny + 1) * (nz + 1)


def contact_nodes(scene) -> int:
    nx, ny, _ = level_counts(scene.fem.mesh)
    return (nx + 1) * (ny + 1)


def friction_updates(scene) -> int:
    """Friction-law updates a node takes in a step of the FE loop (its sub-steps)."""
    from .fem.model.contact import MAX_SUBSTEPS
    from .fem.integrators.explicit import explicit_substeps

    return min(explicit_substeps(scene), MAX_SUBSTEPS)


def analytic_beside_steps(scene) -> float:
    """Steps of the analytic stepper an FE run runs beside it (at the scene's time.dt)."""
    return scene.time.T / scene.time.dt


def estimate(scene, fe: bool, full_series: bool = False, series: bool = True) -> dict:
    """Rough needs of one run of ``scene``: steps, rows, memory and disk bytes, seconds;
    ``series``: the run writes its time series (an analytic sweep point writes
    only its scene and summary, POINT_BYTES)."""
    plan = RecordPlan.for_scene(scene, full_resolution_steps(scene))
    # the FE model's F_n; a base moving along Z adds z, z_b, N (analytic/normal.py)
    normal = scene.vibration.normal_amplitude > 0 or scene.vibration.sampled   # z, z_b, N
    columns = len(COLUMNS) + (1 if fe else 0) + (3 if normal else 0)
    series_files = 2 if fe else 1  # an FE run writes the analytic series beside its own
    memory = 3 * plan.rows * columns * 8
    rows_written = plan.rows if full_series else written_rows(scene)
    disk = series_files * rows_written * columns * CSV_BYTES_PER_VALUE if series else POINT_BYTES
    seconds = scene.steps * STEP_SECONDS * (1 if fe else ESTIMATE_RUNS)
    dofs = 0
    if fe:
        dofs = fe_dofs(scene)
        memory += dofs * FE_BYTES_PER_DOF
        seconds += scene.steps * dofs * FE_STEP_SECONDS_PER_DOF
        # on a copy: the friction law these load is cached on the scene, and a scene
        # holding it (a module) could no longer be sent to a sweep's worker processes
        own = copy.copy(scene)
        seconds += scene.steps * contact_nodes(own) * friction_updates(own) * FRICTION_UPDATE_SECONDS
        seconds += analytic_beside_steps(own) * STEP_SECONDS
        if scene.fem.output_every > 0:
            frames = scene.steps // scene.fem.output_every + 2
            disk += frames * (dofs // 3) * VTK_BYTES_PER_NODE
    return {"steps": scene.steps, "rows": plan.rows, "full_rows": plan.steps - plan.full_from + 1,
            "dofs": dofs,
            "memory": memory, "disk": disk, "seconds": seconds}


def check(scenes, fe: bool, out: Path, full_series: bool = False, series: bool = True) -> float:
    """Refuse, before any work, runs of ``scenes`` (one, or a sweep's points,
    run side by side on at most two processes) that cannot fit in this
    machine's memory, in the free disk under ``out``, or in LONGEST_RUN_S;
    ``full_series``: the runs write every kept row of their time series;
    ``series``: they write their time series at all (see estimate). Returns the
    slowest run's estimated seconds. With ``fe``, first a scene the FE model
    cannot run (scene.check_fe_scene)."""
    if fe:
        for scene in scenes:
            check_fe_scene(scene)
    needs = [(scene, estimate(scene, fe, full_series, series)) for scene in scenes]
    if not needs:  # a sweep none of whose points makes a scene: nothing will run
        return 0.0
    scene, worst = max(needs, key=lambda pair: pair[1]["memory"])
    memory = available_memory()
    if worst["memory"] > memory:
        if fe and worst["dofs"] * FE_BYTES_PER_DOF > worst["memory"] / 2:
            raise SceneError("fem.mesh", f"{scene.fem.mesh!r} has {worst['dofs']:,} degrees of "
                                         f"freedom: the FE model needs ~{_bytes(worst['memory'])} "
                                         f"of memory, and {_bytes(memory)} is available")
        full = worst["full_rows"]
        if full > worst["rows"] / 2:   # neither time.T nor time.series_dt changes these rows
            raise SceneError("time.dt", f"{scene.time.dt:g} s keeps every step of the run's last "
                                        f"{full * scene.time.dt:.3g} s (its two averaging windows "
                                        f"of {scene.averaged_cycles} cycles, and the plotted ones): "
                                        f"{full:.3g} rows, whose time series needs "
                                        f"~{_bytes(worst['memory'])} of memory, and {_bytes(memory)} "
                                        "is available: raise time.dt or average fewer cycles "
                                        "(time.average_cycles)")
        raise SceneError("time.T", f"{scene.time.T:g} s at time.dt = {scene.time.dt:g} s is "
                                   f"{worst['steps']:.3g} steps, whose time series (a row every "
                                   f"time.series_dt = {scene.time.series_dt:g} s: {worst['rows']:.3g} "
                                   f"rows) needs ~{_bytes(worst['memory'])} of memory, and "
                                   f"{_bytes(memory)} is available: shorten time.T or raise "
                                   "time.series_dt")
    disk, free = sum(need["disk"] for _, need in needs), free_disk(out)
    if disk > free:
        raise SceneError("time.T", f"the results would take ~{_bytes(disk)} of disk and "
                                   f"{_bytes(free)} is free under {out}: shorten time.T, raise "
                                   "time.series_dt or fem.output_every")
    scene, slowest = max(needs, key=lambda pair: pair[1]["seconds"])
    if slowest["seconds"] > LONGEST_RUN_S:
        raise SceneError("time.T", f"{scene.time.T:g} s at time.dt = {scene.time.dt:g} s is "
                                   f"{slowest['steps']:.3g} steps: ~{_duration(slowest['seconds'])} "
                                   f"of computing (refused beyond {_duration(LONGEST_RUN_S)})")
    return slowest["seconds"]


def check_grid(grid, samples, fe: bool, out: Path, workers: int) -> dict:
    """Refuse, before its points are made, a sweep over ``grid`` (grid.py: its
    ranges are counted, not expanded) that cannot fit on this machine: the
    memory the sweep holds for its points (POINT_MEMORY each, measured: a
    planned point's values, scene, name and record), the disk its points
    write (the costliest of ``samples``, scenes of points that bound the
    grid's cost (grid.samples), times the points) or LONGEST_RUN_S of computing on
    ``workers`` processes (the samples' mean seconds, and POINT_SECONDS, a
    point). One line naming the grid and what it would take; SceneError under
    the grid as its key. Returns {"points", "disk", "seconds"}: the estimates."""
    from .grid import describe, grid_size

    points = grid_size(grid)
    needs = [estimate(scene, fe, series=fe) for scene in samples]
    disk = points * max((need["disk"] for need in needs), default=POINT_BYTES)
    seconds = points * (POINT_SECONDS + sum(need["seconds"] for need in needs) / max(len(needs), 1))
    seconds /= max(1, workers)
    memory = points * POINT_MEMORY
    too_much = []
    if memory > available_memory():
        too_much.append(f"~{_bytes(memory)} of memory to plan them ({_bytes(available_memory())} "
                        "is available)")
    if disk > free_disk(out):
        too_much.append(f"~{_bytes(disk)} of disk ({_bytes(free_disk(out))} is free under {out})")
    if seconds > LONGEST_RUN_S:
        too_much.append(f"~{_duration(seconds)} of computing on {workers} process"
                        f"{'es' if workers > 1 else ''} (refused beyond {_duration(LONGEST_RUN_S)})")
    if too_much:
        raise SceneError(describe(grid), f"{points:,} points would take "
                                         f"{', '.join(too_much)}: give fewer values")
    return {"points": points, "disk": disk, "seconds": seconds}


LONG_SWEEP_POINTS = 20_000   # a sweep of more points is announced: planning them takes seconds


def long_sweep_notice(needs: dict, workers: int) -> str | None:
    """One line announcing a sweep estimated beyond LONG_RUN_S, or of more than
    LONG_SWEEP_POINTS points, else None."""
    if needs["seconds"] <= LONG_RUN_S and needs["points"] <= LONG_SWEEP_POINTS:
        return None
    return (f"vibrofric: a sweep of {needs['points']:,} points, estimated at up to "
            f"~{_duration(needs['seconds'])} of computing on {workers} process"
            f"{'es' if workers > 1 else ''} and ~{_bytes(needs['disk'])} of disk; its points are "
            f"made first (~{_duration(needs['points'] * PLAN_SECONDS)}). Ctrl-C stops it; "
            "finished points are kept")


def long_run_notice(seconds: float) -> str | None:
    """One line announcing a run estimated beyond LONG_RUN_S (a stiff contact's
    friction sub-steps can make a short time.T take days), else None."""
    if seconds <= LONG_RUN_S:
        return None
    return (f"vibrofric: this run is estimated at ~{_duration(seconds)} of computing "
            "(Ctrl-C stops it; nothing is written before it ends)")
