"""A run's plots and the block's picture, drawn by a child process while the run loads and runs.

Drawn in the command's own process, after the stepping, the plots (matplotlib
imported, then the figures drawn) cost a short command nearly half its time
(docs/performance.md, "Design choices measured"). ``vibrofric analytic``
therefore starts this module as a child process first thing, before it imports
numpy. On the other core the child imports matplotlib and draws a throwaway
figure (the fonts loaded, the mathtext parser built) while the command loads
its compiled stepper and steps; then it receives the rows the two plots draw (t
and F_d of the written series, and the rows of its last cycles, not the whole
series) and draws them into the results' stage while the command writes
timeseries.csv:

    with PlotProcess() as plotter:                      # started: importing matplotlib
        ...                                             # scene, stepper, stepping
        with output.staged(target) as stage:
            with plotter.drawing(plots_job(runs, scene, stage)):  # sent: it draws
                ...                                     # scene.toml, summary.json, the CSV
            # here it has finished; had it failed: PlotError

``vibrofric run`` does the same, its child started before the FE model is set
up: it draws three plots (the two above, FE beside analytic, and the FE
model's normal force) and the block's picture (picture.py: matplotlib's 3D
axes, from the node fields of the run's last step, sent with the rows). The
rows are sent as soon as both models have run, and the child draws while the
command writes the time series and the summary (docs/first-answer.md: what
this saves a repeat Fig 7 run).

The kinds of child (``PlotProcess(kind)``): "analytic" (two plots, and the lumped
body's normal force where the base moves along Z), "fe" (three plots and the picture).

A failure on either side fails the run and leaves nothing. The child's is
raised as PlotError (with its traceback) when ``drawing`` ends, inside the
staged block, so the stage is removed. The command's ends the child
(SIGKILL) and reaps it before the stage is removed, so nothing is written
into a removed stage. The child runs in a session of its own, which Ctrl-C
in the terminal does not reach (the command ends it), and ends by itself when
its input closes without rows: the command stopped early, or died.
"""

import contextlib
import os
import pickle
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

DRIVE_FORCE = "drive_force.png"
LAST_CYCLES = "friction_last_cycles.png"
NORMAL_FORCE = "normal_force.png"
PICTURE = "block.png"
KINDS = ("analytic", "fe")
PACKAGE_ROOT = Path(__file__).resolve().parent.parent  # the directory that holds vibrofric
# OpenBLAS, loaded with numpy, starts a thread per further core, which spins a while
# waiting for work. Neither process gives it any, and each needs the other's core
# (docs/performance.md, "Design choices measured").
ONE_BLAS_THREAD = {"OPENBLAS_NUM_THREADS": "1"}


class PlotError(RuntimeError):
    """The plot process failed; the message holds its traceback."""


class PlotProcess:
    """The child process that draws a run's plots (``kind``, one of KINDS; a context
    manager: the child is started on entry, and ended, if still running, and reaped
    on exit)."""

    def __init__(self, kind: str = "analytic"):
        assert kind in KINDS, kind
        # -P and PYTHONPATH: the child imports this very package, not one from its
        # working directory
        path = os.pathsep.join(filter(None, [str(PACKAGE_ROOT), os.environ.get("PYTHONPATH")]))
        self.process = subprocess.Popen(
            [sys.executable, "-P", "-m", __name__, kind], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, env={**os.environ, "PYTHONPATH": path, **ONE_BLAS_THREAD},
            start_new_session=True)

    def __enter__(self):
        return self

    def __exit__(self, *failure):
        self.stop()

    def stop(self) -> None:
        """End the child if it is still running, and reap it."""
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait()
        with contextlib.suppress(BrokenPipeError):  # the rest of a job it never read
            self.process.stdin.close()
        self.process.stdout.close()

    @contextlib.contextmanager
    def drawing(self, job: dict):
        """Send ``job`` (plots_job); the child draws it while the block
        runs. At the block's end wait for the child: PlotError if it failed. If
        anything fails before, the child is ended and reaped first."""
        try:
            self._send(job)
            yield
            report = self.process.stdout.read()  # what it says, if it fails
            failed = self.process.wait() != 0
        except BaseException:
            self.stop()
            raise
        if failed:
            raise PlotError(f"the plot process failed (exit {self.process.returncode}):\n"
                            f"{report.decode(errors='replace').rstrip()}")

    def _send(self, job: dict) -> None:
        """Write ``job`` to the child and close its input. A child that failed reads
        its input to the end before it exits, so that this never writes into a
        closed pipe: SIGPIPE, which Python ignores, kills the process once a
        library has reset it (importing dolfinx does); one killed from outside
        has closed its end (its exit, read after, says so)."""
        with contextlib.suppress(BrokenPipeError):
            with self.process.stdin:
                pickle.dump(job, self.process.stdin, protocol=pickle.HIGHEST_PROTOCOL)


@contextlib.contextmanager
def one_blas_thread():
    """Within: numpy, imported here for the first time, starts OpenBLAS without
    threads of its own (ONE_BLAS_THREAD), unless the user's environment says
    otherwise; the environment is restored after."""
    added = {name: value for name, value in ONE_BLAS_THREAD.items() if name not in os.environ}
    os.environ.update(added)
    try:
        yield
    finally:
        for name in added:
            os.environ.pop(name, None)


def plots_job(runs: dict, scene, directory: Path, fe=None, picture=None, steady=(),
              fe_steady: bool = False) -> dict:
    """What the plots of ``runs`` (a label to a TimeSeries) draw into ``directory``;
    with ``fe``, an FE run's TimeSeries, its normal force plot too (``fe_steady``: the
    run answered by its steady cycle), and where another of ``runs`` has N (the base
    moves along Z) the lumped N on the same plot; without, the lumped body's normal
    force N of a run whose base moves along Z (its series has N); with ``picture``, the FE run's
    last node fields (FEResult.fields), the block's picture too. ``steady``: the labels of the runs
    answered by their steady cycle (steady_labels), drawn against the base's phase
    where all are (plots.drive_force_figure)."""
    job = {"directory": Path(directory).absolute(), "scene": plotted_scene(scene),
           "steady": tuple(steady), **plotted_rows(runs, scene)}
    if fe is not None:
        job["normal"] = SimpleNamespace(t=fe.t, extra={"F_n": fe.extra["F_n"]})
        job["normal_steady"], job["normal_column"] = fe_steady, "F_n"
        lumped = [(label, series) for label, series in runs.items()
                  if series is not fe and "N" in series.extra]
        if lumped:   # a base moving along Z: the lumped N beside the FE sum
            label, series = lumped[0]
            job["lumped_normal"] = SimpleNamespace(t=series.t, extra={"N": series.extra["N"]})
            job["normal_steady"] = fe_steady and label in steady
    else:   # the analytic command's one run, where its base moves along Z
        lumped = [(label, series) for label, series in runs.items() if "N" in series.extra]
        if lumped:
            label, series = lumped[0]
            job["normal"] = SimpleNamespace(t=series.t, extra={"N": series.extra["N"]})
            job["normal_steady"], job["normal_column"] = label in steady, "N"
    if picture is not None:
        from .picture import picture_rows

        job["picture"] = picture_rows(picture)
    return job


def steady_labels(summaries: dict) -> tuple:
    """The labels of ``summaries`` (a label to a run's summary) whose answer is their
    steady cycle (the summary's periodic block says method "periodic")."""
    return tuple(label for label, summary in summaries.items()
                 if (summary.get("periodic") or {}).get("method") == "periodic")


def plotted_scene(scene) -> SimpleNamespace:
    """The scene's values the run plots read (see plots), as plain values: a Scene
    holds its friction law's module, and unpickled would import numba."""
    vibration = scene.vibration
    return SimpleNamespace(
        name=scene.name, F_c=scene.F_c, vibrated=scene.vibrated,
        contact=SimpleNamespace(F_N=scene.contact.F_N),
        vibration=SimpleNamespace(f=vibration.f, k_v=vibration.k_v,
                                  theta_deg=vibration.theta_deg, t_on=vibration.t_on))


def plotted_rows(runs: dict, scene) -> dict:
    """What each plot draws of every run: t and F_d of every row (drive_force.png),
    and the rows of the last PLOT_CYCLES cycles (friction_last_cycles.png)."""
    from .core.series import PLOT_CYCLES

    return {"whole": {label: SimpleNamespace(t=series.t, F_d=series.F_d)
                      for label, series in runs.items()},
            "last_cycles": {label: series.tail(PLOT_CYCLES / scene.vibration.f)
                            for label, series in runs.items()}}


def warm_up(plots) -> None:
    """Draw a small throwaway figure with the kinds of text of the run plots
    (mathtext, a legend, tick labels): the fonts load and the mathtext parser
    is built while the command still steps, not after it."""
    fig, ax = plots.figure((2, 1), plots.RUN_DPI)
    ax.plot([0.0, 1.0], [0.0, 1.0], label="$F_x$")
    ax.set_title(r"$k_v$ = 1, $\theta$ = 0°, $\mu F_N$")
    ax.legend(fontsize=8)
    fig.canvas.draw()


def serve(kind: str) -> None:
    """The child: import matplotlib, warm up, then draw the job the command sends
    on stdin; nothing to draw if stdin closes first."""
    from . import picture, plots

    warm_up(plots)
    if kind == "fe":
        picture.warm_up()
    try:
        job = pickle.load(sys.stdin.buffer)
    except EOFError:
        return
    directory = job["directory"]
    if "picture" in job:
        picture.draw(job["picture"], directory / PICTURE)
    steady = job["steady"]
    plots.drive_force_history(job["whole"], job["scene"], directory / DRIVE_FORCE, steady)
    plots.friction_last_cycles(job["last_cycles"], job["scene"], directory / LAST_CYCLES)
    if "normal" in job:
        plots.normal_force_history(job["normal"], job["scene"], directory / NORMAL_FORCE,
                                   job["normal_steady"], job["normal_column"],
                                   job.get("lumped_normal"))


if __name__ == "__main__":
    code = 0
    try:
        serve(sys.argv[1] if len(sys.argv) > 1 else "analytic")
    except BaseException:  # reported to the command through stdout, which it reads
        import traceback

        sys.stdout.write(traceback.format_exc())
        sys.stdout.flush()
        sys.stdin.buffer.read()  # what the command still sends (PlotProcess._send)
        code = 1
    sys.stdout.flush()
    sys.stderr.flush()
    # Like multiprocessing's workers, end without the interpreter's teardown of all of
    # matplotlib's objects, which the command would wait for; the PNGs are closed.
    os._exit(code)
