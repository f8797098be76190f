"""The ``vibrofric`` command (spec/interface.md)."""

import argparse
import json
import sys
from pathlib import Path

from . import output, plots
from . import scene as scene_module
from .analytic.series import NumericalError
from .scene import SceneError

EXIT_BAD_INPUT = 2
EXIT_NUMERICAL = 3
EXIT_POINTS_FAILED = 4   # a sweep finished, but some of its points failed
EXIT_INTERRUPTED = 130   # Ctrl-C or SIGTERM, as a shell reports SIGINT
FAILURES_LISTED = 10     # failed points named on stderr; results.csv has them all


def _scene_arguments(parser):
    parser.add_argument("scene", type=Path, help="scene file (TOML)")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="SECTION.KEY=VALUE", help="override a scene key (repeatable)")
    parser.add_argument("--out", type=Path, help="results directory (default results/<scene>-<time>/)")
    parser.add_argument("--json", action="store_true", help="print one JSON document to stdout")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="vibrofric",
        description="Drive force and friction of a body sliding over an in-plane vibrating base.")
    commands = parser.add_subparsers(dest="command", required=True)

    analytic = commands.add_parser("analytic", help="the lumped analytic stepper")
    _scene_arguments(analytic)
    analytic.add_argument("--stepper", choices=("coupled", "longitudinal"), default="coupled",
                          help="coupled two-phase model (default) or the 1D longitudinal model [23]")

    run = commands.add_parser("run", help="the FE simulation, and the analytic stepper on the same scene")
    _scene_arguments(run)

    sweep = commands.add_parser("sweep", help="a batch over a grid of scene values")
    _scene_arguments(sweep)
    sweep.add_argument("--grid", action="append", required=True, metavar="KEY=VALUES",
                       help="a grid axis: comma list or start:stop:count (repeatable)")
    sweep.add_argument("--fe", action="store_true",
                       help="run the FE model (and the analytic stepper) at every point")
    sweep.add_argument("--workers", type=int,
                       help="processes, one run each (default: both cores; under mpirun: the ranks)")

    bench = commands.add_parser("bench", help="speed against error of every method, side by side")
    bench.add_argument("--out", type=Path, help="directory for bench.md and bench.png "
                                                "(default results/bench-<time>/)")
    bench.add_argument("--quick", action="store_true", help="the reduced set, under 2 minutes")
    return parser


def _number(value, form: str = ".4f") -> str:
    """A result for people: ``none`` where there is no value (F_dv/F_d0 without friction)."""
    return "none" if value is None else format(value, form)


def _emit(args, document, text: str) -> None:
    print(json.dumps(document, indent=2) if args.json else text)


def cmd_analytic(args) -> None:
    from .analytic.run import run

    scene = scene_module.load(args.scene, args.overrides)
    series, summary = run(scene, args.stepper)
    target = args.out or output.default_dir(scene.name)
    with output.staged(target) as stage:
        output.write_scene(stage, scene)
        output.write_summary(stage, {"analytic": summary, "stepper": args.stepper})
        output.write_timeseries(stage, series)
        runs = {args.stepper: series}
        plots.drive_force_history(runs, scene, stage / "drive_force.png")
        plots.friction_last_cycles(runs, scene, stage / "friction_last_cycles.png")
    _emit(args, {**summary, "out": str(target)},
          f"F_dv/F_d0 = {_number(summary['F_dv_over_F_d0'])} (F_dv = {summary['F_dv']:.4f} N, "
          f"F_d0 = {summary['F_d0']:.4f} N) in {summary['wall_time_s']:.3f} s; results in {target}")


def cmd_run(args) -> None:
    from .picture import block_picture
    from .runs import fe_beside_analytic

    scene = scene_module.load(args.scene, args.overrides)
    target = args.out or output.default_dir(scene.name)
    with output.staged(target) as stage:
        done = fe_beside_analytic(scene, stage)
        document = {**done.document, "out": str(target)}
        output.write_summary(stage, {**document, "fe_info": done.fe_info})
        runs = {"FE": done.fe.series, "analytic": done.analytic_series}
        plots.drive_force_history(runs, scene, stage / "drive_force.png")
        plots.friction_last_cycles(runs, scene, stage / "friction_last_cycles.png")
        plots.normal_force_history(done.fe.series, scene, stage / "normal_force.png")
        if done.fe_info["frames"]:
            block_picture(stage / "paraview" / "block.pvd", stage / "block.png")
    fe, analytic = document["fe"], document["analytic"]
    settled = (f", settled at {fe['stop_time_s']:g} s, {fe['saving']:.0%} of the steps saved"
               if fe["stopped_early"] else "")
    _emit(args, document,
          f"F_dv/F_d0: FE {_number(fe['F_dv_over_F_d0'])} ({fe['integrator']}, {fe['dofs']} DOFs, "
          f"{fe['wall_time_s']:.1f} s{settled}), analytic {_number(analytic['F_dv_over_F_d0'])}; "
          f"relative difference {_number(document['rel_error'], '.2%')}; results in {target}")


def cmd_sweep(args) -> int:
    from .batch import run_sweep
    from .grid import parse_grid

    scene = scene_module.load(args.scene, args.overrides)
    grid = [parse_grid(text) for text in args.grid]
    outcome = run_sweep(scene, grid, "fe" if args.fe else "analytic", args.out, args.workers)
    if outcome.leader:  # under mpirun, rank 0 speaks for all
        if args.json:
            print(json.dumps(outcome.records, indent=2))
        print(outcome.summary_line(), file=sys.stderr)
        for record in outcome.failed[:FAILURES_LISTED]:
            print(f"  failed {outcome.name(record)}: {record['error']}", file=sys.stderr)
    return EXIT_POINTS_FAILED if outcome.failed else 0


def cmd_bench(args) -> None:
    from . import bench

    plan = bench.QUICK if args.quick else bench.FULL
    result = bench.bench(plan, progress=lambda text: print(text, file=sys.stderr))
    table = bench.markdown(result)
    target = args.out or output.default_dir("bench")
    with output.staged(target) as stage:
        (stage / "bench.md").write_text(table)
        bench.plot(result, stage / "bench.png")
    print(table)


COMMANDS = {"analytic": cmd_analytic, "bench": cmd_bench, "run": cmd_run, "sweep": cmd_sweep}


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return COMMANDS[args.command](args) or 0
    except KeyboardInterrupt:
        print("vibrofric: interrupted; what had finished is kept: rerun the same command "
              "to resume", file=sys.stderr)
        return EXIT_INTERRUPTED
    except SceneError as err:
        print(f"vibrofric: invalid scene: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except NumericalError as err:
        print(f"vibrofric: numerical trouble: {err}", file=sys.stderr)
        return EXIT_NUMERICAL


if __name__ == "__main__":
    sys.exit(main())
