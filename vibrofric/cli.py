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
    sweep.add_argument("--workers", type=int, help="processes (default: both cores)")
    return parser


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
          f"F_dv/F_d0 = {summary['F_dv_over_F_d0']:.4f} (F_dv = {summary['F_dv']:.4f} N, "
          f"F_d0 = {summary['F_d0']:.4f} N) in {summary['wall_time_s']:.3f} s; results in {target}")


def cmd_run(args) -> None:
    from .analytic.run import run
    from .analytic.summary import summarize
    from .fem import run_fe
    from .picture import block_picture

    scene = scene_module.load(args.scene, args.overrides)
    target = args.out or output.default_dir(scene.name)
    with output.staged(target) as stage:
        fe = run_fe(scene, vtk_dir=stage / "paraview")
        analytic_series, analytic = run(scene)
        fe_summary = {**summarize(fe.series, scene, fe.info["wall_time_s"]),
                      "dofs": fe.info["dofs"], "contact_nodes": fe.info["contact_nodes"]}
        rel_error = (abs(fe_summary["F_dv_over_F_d0"] - analytic["F_dv_over_F_d0"])
                     / analytic["F_dv_over_F_d0"])
        document = {"fe": fe_summary, "analytic": analytic, "rel_error": rel_error, "out": str(target)}
        info = {**fe.info, "vtk": "paraview/block.pvd" if fe.info["frames"] else None}
        output.write_scene(stage, scene)
        output.write_summary(stage, {**document, "fe_info": info})
        output.write_timeseries(stage, fe.series)
        output.write_timeseries(stage, analytic_series, "analytic_timeseries.csv")
        runs = {"FE": fe.series, "analytic": analytic_series}
        plots.drive_force_history(runs, scene, stage / "drive_force.png")
        plots.friction_last_cycles(runs, scene, stage / "friction_last_cycles.png")
        plots.normal_force_history(fe.series, scene, stage / "normal_force.png")
        if fe.info["frames"]:
            block_picture(stage / "paraview" / "block.pvd", stage / "block.png")
    _emit(args, document,
          f"F_dv/F_d0: FE {fe_summary['F_dv_over_F_d0']:.4f} ({fe_summary['dofs']} DOFs, "
          f"{fe_summary['wall_time_s']:.1f} s), analytic {analytic['F_dv_over_F_d0']:.4f}; "
          f"relative difference {rel_error:.2%}; results in {target}")


def cmd_sweep(args) -> None:
    from .analytic.sweep import parse_grid, sweep

    scene = scene_module.load(args.scene, args.overrides)
    grid = [parse_grid(text) for text in args.grid]
    records = sweep(scene, grid, workers=args.workers, progress=not args.json)
    target = args.out or output.default_dir(f"{scene.name}-sweep")
    keys = [key for key, _ in grid]
    with output.staged(target) as stage:
        output.write_scene(stage, scene)
        output.write_results_csv(stage, records)
        if keys == ["vibration.k_v"]:
            plots.ratio_against_kv(records, scene, stage / "ratio_against_kv.png")
        elif sorted(keys) == ["vibration.k_v", "vibration.theta_deg"]:
            plots.ratio_against_angle(records, stage / "ratio_against_angle.png")
    ratios = [r["F_dv_over_F_d0"] for r in records]
    _emit(args, records, f"{len(records)} points, F_dv/F_d0 from {min(ratios):.4f} to "
                         f"{max(ratios):.4f}; results in {target}")


COMMANDS = {"analytic": cmd_analytic, "run": cmd_run, "sweep": cmd_sweep}


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        COMMANDS[args.command](args)
    except SceneError as err:
        print(f"vibrofric: invalid scene: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except NumericalError as err:
        print(f"vibrofric: numerical trouble: {err}", file=sys.stderr)
        return EXIT_NUMERICAL
    return 0


if __name__ == "__main__":
    sys.exit(main())
