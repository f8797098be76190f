"""The ``vibrofric`` command (docs/command-line.md)."""

import os
import signal
import sys


def _interrupted_while_starting(signum, frame):
    """Ctrl-C or SIGTERM before the command has begun (while Python imports it or
    reads its arguments): nothing is written yet, so it ends at once, exit 128 +
    the signal's number (130, 143), as it would a moment later (main's
    interruptible() takes over from here)."""
    os.write(2, b"vibrofric: interrupted while starting; nothing was written\n")
    os._exit(128 + signum)


# the command's own process (not main() called from Python: a test, a notebook)
OWN_PROCESS = __name__ == "__main__" or os.path.basename(sys.argv[0]) == "vibrofric"
if OWN_PROCESS:
    for _number in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(_number) is not signal.SIG_IGN:  # a background job's stays ignored
            signal.signal(_number, _interrupted_while_starting)

import argparse  # noqa: E402 (after the handlers: an import can take a while under load)
import atexit  # noqa: E402
import contextlib  # noqa: E402
import errno  # noqa: E402
import faulthandler  # noqa: E402
import gc  # noqa: E402
import json  # noqa: E402
from pathlib import Path  # noqa: E402

# Imported here: only what every command needs, and light (no numpy). The scene
# module (and with it numba), numpy and matplotlib are imported by the commands
# themselves: ``analytic`` starts its plot process before (plot_worker).
from . import __version__, output  # noqa: E402
from .answer_text import accuracy_warning, answer_with_error, value_with_error  # noqa: E402
from .core.errors import (BodyLeftContact, ContactBeyondInterface, NumericalError,  # noqa: E402
                          Refusal)
from .output import OutputError  # noqa: E402
from .library_logs import quiet_libraries  # noqa: E402
from .parallel import interruptible, launcher_rank  # noqa: E402

EXIT_FAILED = 1          # something failed that is not the input's fault (a full disk, a bug)
EXIT_BAD_INPUT = 2
EXIT_NUMERICAL = 3
EXIT_POINTS_FAILED = 4   # a sweep finished, but some of its points failed
EXIT_INTERRUPTED = 130   # Ctrl-C, as a shell reports SIGINT (128 + 2)
EXIT_TERMINATED = 143    # SIGTERM (128 + 15)
FAILURES_LISTED = 10     # failed points named on stderr; results.csv has them all

# At exit, leave every object to the end of the process instead of to the cyclic
# collector: with numba and matplotlib loaded, the interpreter's teardown would
# traverse them all at every pass (docs/performance.md, "Design choices measured"). Every exit
# handler (files, loggers, pools) still runs.
atexit.register(gc.freeze)


class HelpFormatter(argparse.HelpFormatter):
    """Fills in the written series' constants, named {ROWS_PER_CYCLE} and {PLOT_CYCLES}
    in a help text, when help is shown: their module (core.series) imports numpy,
    which a command would otherwise import before it starts (see the imports)."""

    def _get_help_string(self, action):
        from .core.series import PLOT_CYCLES, ROWS_PER_CYCLE

        return (action.help.replace("{ROWS_PER_CYCLE}", str(ROWS_PER_CYCLE))
                .replace("{PLOT_CYCLES}", str(PLOT_CYCLES)))


class Parser(argparse.ArgumentParser):
    """argparse with its complaints on one line, exit 2, and HelpFormatter."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message):
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: {message} (see {self.prog} --help)\n")


def _workers(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--workers {text!r}: expected a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"--workers {value}: at least 1 process is needed")
    return value


def _out_argument(parser, what: str):
    parser.add_argument("--out", type=Path, help=f"{what} (default results/<scene>-<time>/); an "
                                                 "existing directory is written only if empty or, "
                                                 "with --force, if vibrofric wrote it")
    parser.add_argument("--force", action="store_true",
                        help="replace an earlier results directory of vibrofric at --out")


def _scene_arguments(parser):
    parser.add_argument("scene", type=Path,
                        help="scene file (TOML), or a shipped scene: longitudinal, transverse, coupled, "
                             "ball, pin")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="SECTION.KEY=VALUE", help="override a scene key (repeatable)")
    _out_argument(parser, "results directory")
    parser.add_argument("--json", action="store_true", help="print one JSON document to stdout")
    parser.add_argument("--verbose", action="store_true",
                        help="with a refusal, the whole message behind its one line "
                             "(numba's, for a friction law it cannot compile)")


def _series_argument(parser):
    parser.add_argument("--full-series", action="store_true",
                        help="write every kept row of the time series (every step of the last "
                             "two averaging windows, one every time.series_dt before them; every "
                             "step if time.series_dt = time.dt) instead of the default: a row "
                             "every 1/({ROWS_PER_CYCLE} f), rounded down to a multiple of "
                             "time.series_dt, and every step of the last {PLOT_CYCLES} cycles")


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="vibrofric",
        description="Drive force and friction of a body sliding over an in-plane vibrating base.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=Parser)

    analytic = commands.add_parser("analytic", help="the lumped analytic stepper")
    _scene_arguments(analytic)
    analytic.add_argument("--stepper", choices=("coupled", "longitudinal"), default="coupled",
                          help="coupled two-phase model (default) or the 1D longitudinal model [23] "
                               "(Dahl, vibration along X: theta 0 or 180 deg)")
    _series_argument(analytic)

    run = commands.add_parser("run", help="the FE simulation, and the analytic stepper on the same scene")
    _scene_arguments(run)
    _series_argument(run)

    sweep = commands.add_parser(
        "sweep", help="a batch over a grid of scene values",
        description="A batch over a grid of scene values. Rerun into the same --out to resume: "
                    "finished points are kept; --force starts the sweep afresh.")
    _scene_arguments(sweep)
    sweep.add_argument("--grid", action="append", required=True, metavar="KEY=VALUES",
                       help="a grid axis: comma list or start:stop:count (repeatable)")
    sweep.add_argument("--fe", action="store_true",
                       help="run the FE model (and the analytic stepper) at every point")
    sweep.add_argument("--workers", type=_workers,
                       help="processes, one run each (default: both cores; never more than the "
                            "points that can run side by side, nor than the cores without "
                            "--oversubscribe; under mpirun: the ranks)")
    sweep.add_argument("--oversubscribe", action="store_true",
                       help="with --workers N: start N processes even beyond this machine's cores")

    bench = commands.add_parser("bench", help="speed against error of every method, side by side")
    _out_argument(bench, "directory for bench.md and bench.png")
    bench.add_argument("--quick", action="store_true", help="the reduced set, under 2 minutes")

    keys = commands.add_parser("keys", help="every key of a scene: its value, default, unit "
                                            "and meaning")
    keys.add_argument("scene", type=Path, nargs="?",
                      help="scene file (TOML), or a shipped scene: longitudinal, transverse, "
                           "coupled (default: every key at its default)")
    keys.add_argument("--set", dest="overrides", action="append", default=[],
                      metavar="SECTION.KEY=VALUE", help="override a scene key (repeatable)")
    keys.add_argument("--json", action="store_true", help="print one JSON document to stdout")

    commands.add_parser("warm", help="compile the built-in friction laws' loops now (make setup "
                                     "does): later runs start at once")
    return parser


def _number(value, form: str = ".4f") -> str:
    """A result for people: ``none`` where there is no value (F_dv/F_d0 without friction)."""
    return "none" if value is None else format(value, form)


def _emit(args, document, text: str) -> None:
    print(json.dumps(document, indent=2) if args.json else text)


def _warn_unsettled(summary: dict, label: str = "") -> None:
    from .analytic.summary import unsettled_warning

    warning = unsettled_warning(summary, label)
    if warning:
        print(f"vibrofric: {warning}", file=sys.stderr)


def _warn_inaccurate(summary: dict, label: str = "") -> None:
    """The warning on stderr where the answer's step error exceeds time.accuracy."""
    warning = accuracy_warning(summary, label)
    if warning:
        print(f"vibrofric: {warning}", file=sys.stderr)


def _target(args, command: str):
    """(directory, claimed): --out once checked (output.check_target) and locked
    for the rest of the command (output.locked: a second writer is refused at
    once), or a fresh default name claimed for this run."""
    if args.out is None:
        return None, True
    return _locked_out(args, command)[0], False


def _locked_out(args, command: str):
    """--out checked, locked, checked again (it may have changed before the lock
    was taken), and cleared of what a killed run left beside it: (the directory
    written, what check_target says of it). A symlink's folder is the directory."""
    output.check_target(args.out, command, args.force)
    target = args.held.enter_context(output.locked(args.out))
    verdict = output.check_target(target, command, args.force)
    cleared = output.clear_leftovers(target)
    if cleared:
        print(f"vibrofric: removed what a killed run left beside {target}: {', '.join(cleared)}",
              file=sys.stderr)
    return target, verdict


def cmd_analytic(args) -> None:
    from .plot_worker import PlotProcess, one_blas_thread, plots_job, steady_labels

    with PlotProcess() as plotter:  # first: it imports matplotlib while numba loads here
        with one_blas_thread():  # numpy loads here: no BLAS threads to spin on the other core
            from . import budget
            from . import scene as scene_module
            from .analytic.solve import solve
            from .api import check_stepper, scene_file
            from .core.series import written

        scene = scene_module.load(scene_file(args.scene), args.overrides)
        check_stepper(scene, args.stepper)
        target, claim = _target(args, "analytic")
        _announce(budget.long_run_notice(budget.check([scene], fe=False,
                                                      out=target or Path("results"),
                                                      full_series=args.full_series)))
        series, summary = solve(scene, args.stepper)
        series = written(series, scene, args.full_series)  # the summary is of every kept row
        target = target or output.default_dir(scene.name)
        with output.staged(target, "analytic", claimed=claim) as stage:
            with plotter.drawing(plots_job({args.stepper: series}, scene, stage,
                                           steady=steady_labels({args.stepper: summary}))):
                output.write_scene_and_inputs(stage, scene)
                output.write_summary(stage, {"analytic": summary, "stepper": args.stepper})
                output.write_timeseries(stage, series)
    _warn_unsettled(summary)
    _warn_inaccurate(summary)
    how = _periodic_note(summary)
    _emit(args, {**summary, "out": str(target)},
          f"{answer_with_error(summary)} (F_dv = {summary['F_dv']:.4f} N, "
          f"F_d0 = {summary['F_d0']:.4f} N) in {summary['wall_time_s']:.3f} s{how}; "
          f"results in {target}")


class _LoopBar:
    """Progress on stderr for an FE run, called as progress(done, total): a tqdm bar
    over simulated seconds for the time loop (total: time.T), a count of base cycles
    while the steady cycle is shot for (total None: time.method auto or periodic);
    quiet with --json when stderr is not a terminal, and redrawn every 10 s rather
    than 0.5 s into a log file. The time loop's bar is drawn from its first report
    (of 0 done: the loop starting, its code compiled: recording.run_in_chunks), so
    its rate and time left are the loop's alone; a second report of 0 done restarts
    its clock. The count of cycles shows no rate or time left (the shooting stops when
    it converges) and only once it has run for CYCLES_SHOWN_AFTER seconds."""

    CYCLES_SHOWN_AFTER = 1.0   # s: a shooting quicker than this shows nothing but its answer

    def __init__(self, args, what: str, total: float):
        self.what, self.total = what, total
        self.quiet = args.json and not sys.stderr.isatty()
        self.bar = None
        self.counting_cycles = False

    def _open(self, counting_cycles: bool) -> None:
        from tqdm import tqdm

        if self.bar is not None:
            self.bar.close()
        terminal = sys.stderr.isatty()
        common = dict(disable=self.quiet, file=sys.stderr, mininterval=0.5 if terminal else 10.0)
        if counting_cycles:
            self.bar = tqdm(desc=f"{self.what} steady cycle", total=None, unit="cycle",
                            delay=self.CYCLES_SHOWN_AFTER,
                            bar_format="{desc}: {n} base cycles shot [{elapsed}]", **common)
        else:
            self.bar = tqdm(desc=self.what, total=self.total, unit="s",
                            bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.4g}/{total:.4g} "
                                       "s simulated [{elapsed}<{remaining}]", **common)
        self.counting_cycles = counting_cycles

    def __call__(self, done: float, total: float | None) -> None:
        counting_cycles = total is None
        if self.bar is None or counting_cycles != self.counting_cycles:
            self._open(counting_cycles)
        if counting_cycles:
            self.bar.update(done - self.bar.n)
        elif done == 0:
            self.bar.reset()
        else:   # the last step may pass T by a rounding
            self.bar.update(min(done, self.bar.total) - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _announce(line) -> None:
    """``line`` on stderr, if there is one."""
    if line:
        print(line, file=sys.stderr, flush=True)


def cmd_run(args) -> None:
    from . import budget
    from . import scene as scene_module
    from .api import scene_file, write_fe_run

    scene = scene_module.load(scene_file(args.scene), args.overrides)
    target, claim = _target(args, "run")
    _announce(budget.long_run_notice(budget.check([scene], fe=True, out=target or Path("results"),
                                                  full_series=args.full_series)))
    target = target or output.default_dir(scene.name)
    bar = _LoopBar(args, "FE", scene.time.T)
    with output.staged(target, "run", claimed=claim) as stage:
        try:
            document, _ = write_fe_run(scene, stage, bar, args.full_series, out=str(target))
        finally:
            bar.close()
    fe, analytic = document["fe"], document["analytic"]
    _warn_unsettled(fe, "FE")
    _warn_unsettled(analytic, "analytic")
    _periodic_note(analytic, "analytic ")    # its warning where the analytic model stepped
    _warn_inaccurate(analytic, "analytic")
    settled = (f", settled at {fe['stop_time_s']:g} s, {fe['saving']:.0%} of the steps saved"
               if fe["stopped_early"] else "")
    periodic = _periodic_note(fe, "FE ")
    settled += f"; {periodic.strip()[1:-1]}" if periodic else ""
    _warn_inaccurate(fe, "FE")
    _emit(args, document,
          f"F_dv/F_d0: FE {value_with_error(fe, with_step=False)} ({fe['integrator']}, "
          f"dt {fe['dt_used']:.6g} s, {fe['dofs']} DOFs, "
          f"{fe['wall_time_s']:.1f} s{settled}), analytic {value_with_error(analytic)}; "
          f"relative difference {_number(document['rel_error'], '.2%')}; results in {target}"
          + (f"; {fe['normal_force_rule_note']}" if fe.get("normal_force_rule_note") else ""))


def _periodic_note(summary: dict, label: str = "") -> str:
    """The answer's note on the periodic solver (time.method periodic or auto): where it
    answered, its cycles and largest Floquet multiplier; where it did not, a warning
    on stderr saying why the run was stepped."""
    periodic = summary.get("periodic")
    if not periodic:
        return ""
    if periodic["method"] == "transient":
        if periodic["reason"]:
            print(f"warning: no {label}periodic steady state: {periodic['reason']}; stepped "
                  "through time.T instead", file=sys.stderr)
        return ""
    adjusted = (f", at dt = {periodic['dt']:.6g} s for {periodic['steps_per_cycle']} steps a cycle"
                if periodic.get("dt_adjusted") else "")
    return (f" (periodic: {periodic['cycles_integrated']} cycles, largest Floquet multiplier "
            f"{periodic['floquet_max_modulus']:.4f}{adjusted})")


def cmd_sweep(args) -> int:
    from . import scene as scene_module
    from .api import scene_file
    from .batch import run_sweep
    from .grid import parse_grid

    scene = scene_module.load(scene_file(args.scene), args.overrides)
    grid = [parse_grid(text) for text in args.grid]
    from .batch import mpi

    fresh, out = False, None
    comm = mpi.world()
    if args.out is not None and comm is not None and comm.rank != 0:
        out = output.real_target(args.out)  # rank 0 holds the lock for all
        output.check_target(out, "sweep", args.force)
    elif args.out is not None:
        out, verdict = _locked_out(args, "sweep")
        fresh = verdict == "replace"
    outcome = run_sweep(scene, grid, "fe" if args.fe else "analytic", out, args.workers,
                        fresh=fresh, oversubscribe=args.oversubscribe, announce=_announce)
    if outcome.leader:  # under mpirun, rank 0 speaks for all
        if args.json:
            print(json.dumps(outcome.records, indent=2))
        print(outcome.summary_line(), file=sys.stderr)
        for record in outcome.failed[:FAILURES_LISTED]:
            print(f"  failed {outcome.name(record)}: {record['error']}", file=sys.stderr)
    return EXIT_POINTS_FAILED if outcome.failed else 0


def cmd_bench(args) -> None:
    from . import bench

    target, claim = _target(args, "bench")
    plan = bench.QUICK if args.quick else bench.FULL
    result = bench.measure(plan, progress=lambda text: print(text, file=sys.stderr))
    table = bench.markdown(result)
    target = target or output.default_dir("bench")
    with output.staged(target, "bench", claimed=claim) as stage:
        (stage / "bench.md").write_text(table)
        bench.plot(result, stage / "bench.png")
    print(table)


def _shown(value) -> str:
    """A scene value as the keys table shows it (numbers to 12 digits, lists in brackets)."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return f"{value:.12g}"
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_shown(v) for v in value) + "]"
    return str(value)


def cmd_keys(args) -> None:
    from . import scene as scene_module
    from .api import load_scene, scene_file, scene_keys

    if args.scene is not None:
        scene = scene_module.load(scene_file(args.scene), args.overrides)
    else:   # every key at its default, with --set as on any scene
        scene = load_scene({}, **dict(map(scene_module.parse_assignment, args.overrides)))
    table = scene_keys(scene)
    if args.json:
        print(json.dumps(table.to_dict(orient="records"), indent=2, default=list))
        return
    rows = [("key", "value", "default", "unit", "meaning")]
    rows += [(row.key, _shown(row.value), _shown(row.default), row.unit or "-", row.meaning)
             for row in table.itertuples()]
    widths = [max(len(row[i]) for row in rows) for i in range(4)]
    for row in rows:
        print("  ".join(cell.ljust(width) for cell, width in zip(row, widths)) + "  " + row[4])


def cmd_warm(args) -> None:
    from .warm import warm

    warm()


COMMANDS = {"analytic": cmd_analytic, "bench": cmd_bench, "keys": cmd_keys, "run": cmd_run,
            "sweep": cmd_sweep, "warm": cmd_warm}


def _interrupted(command: str, signal_name: str) -> str | None:
    """The line that says what an interrupt left; None in an MPI rank but the first
    (rank 0 speaks for all)."""
    rank = launcher_rank()
    if rank:
        return None
    how = "by SIGTERM" if signal_name == "SIGTERM" else "(Ctrl-C)"
    if signal_name == "SIGTERM" and "OMPI_COMM_WORLD_SIZE" in os.environ:
        how += " (Open MPI's mpirun sends it for a Ctrl-C too)"
    if command == "sweep":
        return (f"vibrofric: sweep interrupted {how}; the finished points are kept: rerun the "
                "same command to resume")
    if output.committed:  # the signal waited for the results to move in (output.commit)
        return (f"vibrofric: {command} interrupted {how} after its results were written: "
                f"results in {output.committed[-1]}")
    return f"vibrofric: {command} interrupted {how}; nothing was written"


def _explained(err: Exception):
    """(message, exit code) for an error the user can act on; None for any other
    (a bug: its traceback is shown). The scene module is imported here, once
    an error is raised, not with this module (see the imports above)."""
    from .friction_law import LawError
    from .scene import SceneError, refused

    if isinstance(err, LawError):  # a user's law failing in a run (friction_law.specialize)
        return f"vibrofric: invalid scene: contact.law: {err}", EXIT_BAD_INPUT
    if isinstance(err, SceneError):
        return f"vibrofric: invalid scene: {err}", EXIT_BAD_INPUT
    if isinstance(err, Refusal):
        return f"vibrofric: invalid scene: {refused(err)}", EXIT_BAD_INPUT
    if isinstance(err, OutputError):
        return f"vibrofric: {err}", EXIT_BAD_INPUT
    if isinstance(err, (BodyLeftContact, ContactBeyondInterface)):
        return f"vibrofric: run stopped: {err}", EXIT_NUMERICAL
    if isinstance(err, NumericalError):
        return f"vibrofric: numerical trouble: {err}", EXIT_NUMERICAL
    return None


DISK_FULL = (errno.ENOSPC, errno.EDQUOT)


def _crash_log(command: str) -> Path | None:
    """Write the traceback being handled to a log file in the user's cache
    directory ($XDG_CACHE_HOME/vibrofric, default ~/.cache/vibrofric); its path."""
    import datetime
    import os
    import traceback

    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "vibrofric"
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    path = base / f"crash-{command}-{stamp}-{os.getpid()}.log"
    try:
        base.mkdir(parents=True, exist_ok=True)
        path.write_text(f"vibrofric {' '.join(sys.argv[1:])}\n\n{traceback.format_exc()}")
    except OSError:
        return None
    return path


def _unexpected(command: str, err: BaseException) -> str:
    """One line for an error that is not the user's to fix: what failed, and
    where the full traceback went."""
    log = _crash_log(command)
    where = f"the full traceback is in {log}" if log else "the traceback could not be written"
    frame = traceback_origin(err)
    return (f"vibrofric: {command} failed unexpectedly: {type(err).__name__}: {err} "
            f"(at {frame}; {where}; please report it)")


def traceback_origin(err: BaseException) -> str:
    """file:line of the innermost frame of ``err``'s traceback."""
    tb = err.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    if tb is None:
        return "?"
    return f"{Path(tb.tb_frame.f_code.co_filename).name}:{tb.tb_lineno}"


def _end_now(code: int) -> None:
    """End the process with ``code`` at once, its output flushed. After an interrupt
    the interpreter's own exit joins concurrent.futures' manager thread of a pool
    whose workers were terminated (parallel.run_on_pool), which on Python 3.12 hung
    once in a loaded test run, past a minute; nothing is left for exit to do."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    quiet_libraries()
    if not faulthandler.is_enabled():  # a crash in compiled code (numba, PETSc) shows its stack
        faulthandler.enable()
    output.committed.clear()
    try:
        with interruptible(), contextlib.ExitStack() as args.held:  # the locks of --out
            return COMMANDS[args.command](args) or 0
    except KeyboardInterrupt as interrupt:
        _announce(_interrupted(args.command, str(interrupt)))
        code = EXIT_TERMINATED if str(interrupt) == "SIGTERM" else EXIT_INTERRUPTED
        from .batch.mpi import launched

        if OWN_PROCESS and not launched():   # what it wrote is cleared, its locks
            _end_now(code)   # released: end here, not in the interpreter's exit (an MPI
        return code          # rank's exit finalizes MPI, which passes on its output)
    except OSError as err:
        if err.errno == errno.EPIPE:   # stdout's reader ended (| head): nothing more to say
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())   # (nor at exit)
            return EXIT_FAILED
        if err.errno in DISK_FULL:
            name = f" writing {err.filename}" if err.filename else ""
            print(f"vibrofric: {args.command} stopped: the disk is full ({err.strerror}){name}; "
                  "nothing half-written was kept", file=sys.stderr)
            return EXIT_FAILED
        print(_unexpected(args.command, err), file=sys.stderr)
        return EXIT_FAILED
    except Exception as err:
        explained = _explained(err)
        if explained is None:
            print(_unexpected(args.command, err), file=sys.stderr)
            return EXIT_FAILED
        message, code = explained
        print(message, file=sys.stderr)
        if getattr(args, "verbose", False) and getattr(err, "detail", ""):
            print(err.detail.rstrip(), file=sys.stderr)
        return code


if __name__ == "__main__":
    status = main()
    # CPython 3.12 under ``python -m``: a KeyboardInterrupt that ended a string exec
    # (numba and dataclasses exec generated source while the command loads) marks
    # the process as interrupted even though main() caught it, and the process
    # then kills itself with SIGINT at exit (status -2, not 130). Any later string
    # exec clears that mark.
    exec("")
    sys.exit(status)
