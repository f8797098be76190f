"""A whole sweep, run to disk: plan, skip what is done, run the rest, report.

    <out>/scene.toml        the base scene, before the grid's values
    <out>/points/<name>/    one directory per grid point (points.py)
    <out>/results.csv       one row per finished point, from the directories (ledger.py)
    <out>/*.png             the study's figures, at the end

Points run on a pool of ``workers`` processes, or serially with one worker,
or, under mpirun, shared out across the ranks (mpi.py). Whichever, a rerun
with the same ``out`` runs only the points whose directories are missing,
failed, or hold another scene or mode; a killed sweep loses only the points
it was running (their partial directories are cleared on the rerun).
"""

import functools
import time
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from .. import budget, output, plots
from .. import scene as scene_module
from ..friction_law.specialize import specialized_first
from ..grid import canonical_grid, grid_size, point_name, samples
from ..parallel import interruptible, run_on_pool, worker_count
from . import mpi
from .ledger import Ledger
from .lanes import lanes
from .points import ERROR, model_kept, neighbour_orbit, plan, run_point, run_point_on_worker

RATIO = "F_dv_over_F_d0"


@dataclass
class Outcome:
    """What a sweep left on disk, as the process reporting it sees it.

    records  every finished point in grid order: grid values, then the result keys or "error"
    leader   True in the process that reports (rank 0 under mpirun)
    """

    records: list
    keys: list
    out: Path
    reused: int
    wall_time_s: float
    leader: bool
    damaged: int = 0  # points found damaged on disk (points.DAMAGED) and run again

    @property
    def failed(self) -> list:
        return [r for r in self.records if ERROR in r]

    def name(self, record) -> str:
        return point_name({key: record[key] for key in self.keys})

    def worst_fe_error(self):
        """(|FE - analytic| / analytic, point) at its largest over the FE points, or None."""
        errors = [(r["rel_error"], self.name(r)) for r in self.records if r.get("rel_error") is not None]
        return max(errors, default=None)

    @property
    def unsettled(self) -> list:
        """Done points with an average that has not settled (analytic.summary.summarize;
        an FE point's FE or analytic run; points written before the flag existed count as settled)."""
        def settled(record) -> bool:
            summaries = [record["fe"], record["analytic"]] if "fe" in record else [record]
            return all(summary.get("settled", True) for summary in summaries)

        return [r for r in self.records if ERROR not in r and not settled(r)]

    def summary_line(self) -> str:
        rerun = f", {self.damaged} found damaged and rerun" if self.damaged else ""
        line = (f"sweep: {len(self.records)} points ({self.reused} reused{rerun}), "
                f"{len(self.failed)} failed, {len(self.unsettled)} unsettled, {self.wall_time_s:.1f} s")
        methods = [method(r) for r in self.records if ERROR not in r]
        if any(m is not None for m in methods):
            # some point's scene asked for its orbit (time.method periodic or auto:
            # analytic/periodic.py, fem/integrators/periodic.py); a point stepped by its
            # time.method (None) is stepped all the same
            stepped = len(methods) - methods.count("periodic")
            line += f"; {methods.count('periodic')} answered by their periodic orbit, {stepped} stepped"
        worst = self.worst_fe_error()
        if worst is not None:
            line += f"; worst |FE - analytic| / analytic {worst[0]:.2%} at {worst[1]}"
        return f"{line}; results in {self.out}"


def method(record) -> str | None:
    """Which method answered a finished point ("periodic" or "transient"; an FE point's
    FE run), or None where the scene's time.method was transient."""
    summary = record["fe"] if isinstance(record.get("fe"), dict) else record
    periodic = summary.get("periodic")
    return periodic.get("method") if isinstance(periodic, dict) else None


class Progress:
    """The bar on stderr: finished points of the grid, done / failed, and the time left.

    It counts what the ledger holds, so under mpirun rank 0's bar also moves
    for the other ranks' points (each time it reads the directories). The time left
    is the rate since the first ``warm_up`` points of this run finished (each
    worker's first point loads its compiled loops, or compiles them for a new law or
    an edited package: seconds to a minute that say nothing of the rest), shown once
    a point has finished after them.
    """

    def __init__(self, ledger: Ledger, enabled: bool, warm_up: int = 1, clock=time.monotonic):
        self.ledger = ledger
        self.clock = clock
        self.bar = tqdm(total=len(ledger.points), initial=len(ledger.records), desc="sweep",
                        unit="point", disable=not enabled,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {n_fmt}/{total_fmt} "
                                   "[{elapsed}{postfix}]")
        self.warm_up_end = len(ledger.records) + warm_up    # points finished when it ends
        self.since = None                                   # (clock, points) then
        self._postfix()

    def _postfix(self):
        failed = len(self.ledger.failed)
        finished = len(self.ledger.records)
        postfix = {"done": finished - failed, "failed": failed}
        if self.since is None and finished >= self.warm_up_end:
            self.since = (self.clock(), finished)
        elif self.since is not None and finished > self.since[1]:
            start, points = self.since
            rate = (finished - points) / max(self.clock() - start, 1e-9)
            postfix["left"] = f"{(len(self.ledger.points) - finished) / rate:.0f} s"
        self.bar.set_postfix(postfix, refresh=False)

    def update(self):
        self._postfix()
        self.bar.update(len(self.ledger.records) - self.bar.n)

    def close(self):
        self.bar.close()


def _prepare(scene, ledger: Ledger, out: Path) -> list:
    """Ready ``out`` for a first run or a rerun; return the indices of the points to run.

    Clears what killed writers left, and the failed points, which run again
    (so that every point directory there is final for this run).
    """
    (out / "points").mkdir(parents=True, exist_ok=True)
    output.write_marker(out, "sweep")
    output.remove_partials(out)
    output.remove_partials(out / "points")
    output.write_scene(out, scene)
    ledger.read()
    for point in ledger.points:
        if point.name in ledger.damaged or (point.name in ledger.records and not ledger.is_done(point)):
            output.remove(point.directory)
    ledger.read()
    ledger.write_csv()
    return [i for i, point in enumerate(ledger.points) if not ledger.is_done(point)]


def _check_same_scene(scene, out: Path) -> None:
    """Resume ``out`` only for the sweep it holds: the same scene and ``--set`` (the
    grid may differ: its common points are reused). Run there, another scene's
    sweep would rewrite the results.csv, scene.toml and figures of the one there;
    it is refused (OutputError) before any work, and ``--force`` replaces it.
    """
    written = out / "scene.toml"
    if not written.is_file():
        return  # a sweep killed before it wrote its scene: nothing of it to keep apart
    new = scene_module.to_dict(scene)
    try:
        earlier = scene_module.to_dict(scene_module.load(written))
    except (scene_module.SceneError, OSError):
        earlier = None
    if earlier == new:
        return
    if earlier is None:
        what = "its scene.toml cannot be read as a scene"
    else:
        differing = [f"{section}.{key}" for section in new
                     for key in sorted(set(new[section]) | set(earlier.get(section, {})))
                     if new[section].get(key) != earlier.get(section, {}).get(key)]
        what = (f"its scene.toml differs in {', '.join(differing[:3])}"
                f"{' and more' if len(differing) > 3 else ''}")
    raise output.OutputError(
        f"--out {out}: holds a sweep of another scene ({what}); resume it with the same "
        "scene and --set, name another --out, or add --force to replace it")


def _figures(ledger: Ledger, keys: list, scene, out: Path) -> None:
    """The study's figures from its done points: F_dv/F_d0 against k_v (Fig 6/9)
    or against theta per k_v (Fig 12), FE markers over the analytic curves; and
    for FE the relative difference per point."""
    rows = [output.flatten(r) for r in ledger.in_grid_order() if ERROR not in r]
    if not rows:
        return
    fe = ledger.mode == "fe"
    curve, markers = (f"analytic.{RATIO}", f"fe.{RATIO}") if fe else (RATIO, None)
    figures = {}
    if keys == ["vibration.k_v"]:
        figures["ratio_against_kv.png"] = functools.partial(
            plots.ratio_against_kv, rows, scene, key=curve, fe_key=markers)
    elif sorted(keys) == ["vibration.k_v", "vibration.theta_deg"]:
        figures["ratio_against_angle.png"] = functools.partial(
            plots.ratio_against_angle, rows, key=curve, fe_key=markers)
    if fe:
        figures["fe_error.png"] = functools.partial(plots.error_per_point, rows, keys)
    for name, draw in figures.items():
        with output.staged_file(out / name) as partial:
            draw(partial)


def _run_by_continuation(todo: list, ledger: Ledger, mode: str, workers: int, finished,
                         comm=None) -> None:
    """time.method periodic or auto: the grid's lanes (lanes.py, a function of the grid
    alone), each point from the orbit of the point before it in its lane: the one that
    lane ran just before, or, where that one was finished by an earlier run (a resumed
    sweep), the orbit its directory holds (points.neighbour_orbit); a lane's first
    point from steady sliding. The lanes with points to run are worked side by side,
    costliest first (expected_cost): on a pool of ``workers`` processes, in this
    process with one, or shared out across the MPI ranks of ``comm``."""
    work = _lanes_to_run(todo, ledger)
    if comm is not None or workers == 1 or len(work) == 1:
        with model_kept(mode):
            for lane in work if comm is None else work[comm.rank::comm.size]:
                _run_lane(lane, mode, finished)
        return
    waiting = list(range(len(work) - 1, -1, -1))   # lane indices, popped from the end

    def next_task(k, orbit=None):
        """Lane k's next point to run, or else the next waiting lane's first, as a task."""
        while k is not None:
            step = work[k].next_step(orbit)
            if step is not None:
                return [(step[0], mode, step[1], k)]   # the lane's index: tasks are pickled
            k, orbit = (waiting.pop() if waiting else None), None
        return []

    def done(task, orbit):
        finished(task[0])
        return next_task(task[3], orbit)

    first = [task for _ in range(min(workers, len(work))) for task in next_task(waiting.pop())]
    run_on_pool(run_point_on_worker, first, workers, done)


class _Lane:
    """One lane's points in lane order, those to run marked, walked once."""

    def __init__(self, points: list, to_run: set):
        self.points = points
        self.to_run = to_run
        self.position = -1          # of the point last handed out

    @property
    def cost(self) -> float:
        return sum(expected_cost(p) for p in self.points if p.name in self.to_run)

    def next_step(self, orbit=None):
        """(point, start) for the lane's next point to run, or None at its end.
        ``orbit``: what the point handed out last returned."""
        ran = self.position
        self.position += 1
        while self.position < len(self.points) and self.points[self.position].name not in self.to_run:
            self.position += 1
        if self.position == len(self.points):
            return None
        if self.position == 0:
            start = None
        elif self.position - 1 == ran:
            start = orbit
        else:   # its neighbour was finished by an earlier run
            start = neighbour_orbit(self.points[self.position - 1].directory)
        return self.points[self.position], start


def _run_lane(lane: _Lane, mode: str, finished) -> None:
    """A lane's points one after the other in this process."""
    orbit = None
    while (step := lane.next_step(orbit)) is not None:
        orbit = run_point(step[0], mode, step[1])
        finished(step[0])


def _lanes_to_run(todo: list, ledger: Ledger) -> list:
    """The grid's lanes that hold points to run, costliest first (grid order among equals)."""
    to_run = {point.name for point in todo}
    found = [_Lane([ledger.points[i] for i in lane], to_run)
             for lane in lanes([point.values for point in ledger.points])]
    return sorted((lane for lane in found if any(p.name in to_run for p in lane.points)),
                  key=lambda lane: -lane.cost)


def expected_cost(point) -> float:
    """A point's expected cost, relative: 1 + k_v. The steady cycle of a harder shaken
    contact costs more: its contact iteration takes more iterations a step and its
    orbit more Newton iterations: on the Fig 12 FE grid (reduced) a point at k_v = 20
    cost about seven times one at k_v = 2 (docs/periodic.md, Speed). A point that
    runs nothing (no valid scene) costs nothing."""
    if point.scene is None:
        return 0.0
    return 1.0 + point.scene.vibration.k_v


@specialized_first
def run_sweep(scene, grid, mode: str, out=None, workers=None, fresh: bool = False,
              oversubscribe: bool = False, announce=None) -> Outcome:
    """Run ``mode`` ("analytic" or "fe") at every point of ``grid`` into ``out``
    (default results/<scene>-sweep-<time>/), resuming what is there, on
    ``workers`` processes (default: both cores; never more than can run side by
    side, nor than the cores unless ``oversubscribe``: parallel.worker_count) or,
    under mpirun, the ranks; ``fresh``: replace what ``out`` holds instead of
    resuming it; ``announce(line)``: told of a long sweep and of fewer workers
    than asked for (default: nothing said).

    Raises SceneError before any work if the grid names an unknown key or a
    point twice, or cannot fit on this machine (budget.check_grid, before its
    points are made); KeyboardInterrupt on Ctrl-C or SIGTERM, with every finished
    point kept, results.csv rewritten from them and no partial directory left.
    """
    start = time.perf_counter()
    announce = announce or (lambda line: None)
    keys = [key for key, _ in grid]
    if mode == "fe":   # before the output directory is made: a scene the FE model refuses
        for sample in [scene, *_sample_scenes(scene, canonical_grid(grid))]:
            scene_module.check_fe_scene(sample)
    comm = mpi.world()
    leader = comm is None or comm.rank == 0
    if out is None and leader:
        out = output.default_dir(f"{scene.name}-sweep")
    if comm is not None:
        out = comm.bcast(out, root=0)  # rank 0's time stamp in the default name
        mpi.end_with_launcher()
    out = Path(out)
    grid = canonical_grid(grid)
    sampled = _sample_scenes(scene, grid)
    planned_workers = comm.size if comm is not None else worker_count(
        workers, grid_size(grid), oversubscribe)[0]
    budget.check(sampled, mode == "fe", out, series=mode == "fe")  # one run's needs, its key named
    needs = budget.check_grid(grid, sampled, mode == "fe", out, planned_workers)
    if leader:
        announce(budget.long_sweep_notice(needs, planned_workers))
    ledger = Ledger(plan(scene, grid, out / "points"), mode, out)
    if fresh and leader and out.exists():
        output.remove(out)
    elif out.exists():
        _check_same_scene(scene, out)
    todo = _prepare(scene, ledger, out) if leader else None
    if comm is not None:
        todo = comm.bcast(todo, root=0)  # rank 0's reading of the directories, for all
    todo = [ledger.points[i] for i in todo]
    reused = len(ledger.points) - len(todo)
    continued = scene.time.method != "transient"
    if comm is None:
        side_by_side = len(_lanes_to_run(todo, ledger)) if continued else len(todo)
        worker_bytes = budget.WORKER_BYTES + max(
            (budget.estimate(s, mode == "fe", series=False)["memory"] for s in sampled), default=0)
        workers, note = worker_count(workers, side_by_side, oversubscribe, worker_bytes,
                                     budget.available_memory(),
                                     "lanes of points" if continued else "points")
        announce(note)
    # each worker's (or rank's) first point loads or compiles its loops: not in the rate
    bar = Progress(ledger, enabled=leader, warm_up=comm.size if comm is not None else workers)

    def finished(point, _result=None):
        # under mpirun the other ranks' points land too: read every directory
        ledger.read(None if comm is not None else [point])
        ledger.write_csv(throttled=True)
        bar.update()

    run = functools.partial(run_point, mode=mode)
    try:
        with interruptible():
            if continued:
                _run_by_continuation(todo, ledger, mode, workers, finished, comm)
            elif comm is None and workers > 1:
                run_on_pool(run, todo, workers, finished)
            else:
                for point in todo if comm is None else mpi.share(todo, comm):
                    run(point)
                    finished(point)
            if comm is not None:
                mpi.wait_for_all(comm)
    finally:
        if comm is None:   # the pool's workers are gone: what they were writing goes too
            output.remove_partials(out / "points")
            # the points this process has not read yet (one whose result was on its way
            # when the sweep stopped): reading every directory again would keep Ctrl-C
            # waiting 0.7 s at 500 points (each one's checks.json verified)
            ledger.read([point for point in todo if point.name not in ledger.records])
        else:   # the other ranks' points
            ledger.read()
        if leader:
            ledger.write_csv()
        bar.update()
        bar.close()
    if leader:
        _figures(ledger, keys, scene, out)
    return Outcome(ledger.in_grid_order(), keys, out, reused,
                   time.perf_counter() - start, leader, len(ledger.damaged))


def _sample_scenes(scene, grid) -> list:
    """The scenes of the grid's samples (grid.samples) that make one: what bounds a
    point's cost, estimated before the grid is expanded."""
    scenes = []
    for values in samples(grid):
        try:
            scenes.append(scene.with_values(values))
        except scene_module.SceneError:
            pass   # that point will fail alone
    return scenes
