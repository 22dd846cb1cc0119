"""The ``axmpm`` command.

Exit codes: 0 success; 2 bad input (scenario, overrides, output folder, a run folder another
process is writing), one ``error: dotted.key: message`` line per problem on stderr and no
traceback; 3 the run failed: the simulation (the engine's reason) or writing its output (the
file and the reason), printed and recorded in summary.json wherever it can still be written;
130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import __version__
from .cases.column_1d.demo import run_demo
from .cases.column_collapse.demo import model_description, run_collapse_demo
from .engine import core
from .errors import EXIT_INPUT, EXIT_INTERRUPTED, EXIT_OK, RunError, ScenarioError
from .run import run
from .run.estimate import estimate_run
from .run.runner import THREADS_DEFAULT, THREADS_HELP, report_run, thread_count
from .scenario import Scenario, schema_json


def version_text() -> str:
    """``axmpm VERSION (engine VERSION, INSTRUCTION_SET)``: the installed package's version and
    the compiled engine's, with the instruction set its loops run with on this CPU."""
    try:
        engine = core()
    except ImportError:
        return f"axmpm {__version__} (engine not built: run `make install`)"
    return f"axmpm {__version__} (engine {engine.__version__}, {engine.instruction_set()})"


class _VersionAction(argparse.Action):
    """``--version``: like argparse's, but the engine is loaded only when asked."""

    def __init__(self, option_strings: list[str], dest: str = argparse.SUPPRESS, **kwargs: object):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS,
                         help="print the version of axmpm and of its engine, then exit")

    def __call__(self, parser: argparse.ArgumentParser, *args: object, **kwargs: object) -> None:
        print(version_text())
        parser.exit()


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="axmpm",
        description="Material point method for large-deformation geomechanics "
        "(plane strain and axisymmetric).",
    )
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    set_help = "override a scenario value, e.g. --set materials.sand.density=1600 (repeatable)"

    p = sub.add_parser("run", help="run a scenario and write its output folder")
    p.add_argument("scenario", type=Path, help="scenario TOML file")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE", help=set_help)
    p.add_argument("--overwrite", action="store_true", help="replace a non-empty folder that is not an axmpm run")
    p.add_argument("--threads", type=thread_count, default=0, help=THREADS_HELP)
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="show a progress bar (default: when stderr is a terminal)")

    p = sub.add_parser("check", help="validate a scenario and report every error")
    p.add_argument("scenario", type=Path, help="scenario TOML file")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE", help=set_help)
    p.add_argument("--print", dest="print_resolved", action="store_true",
                   help="print the resolved scenario (every default filled in)")
    p.add_argument("--estimate", action=argparse.BooleanOptionalAction, default=True,
                   help="build the run and time a few steps to estimate the run time (default: on)")
    p.add_argument("--threads", type=thread_count, default=0,
                   help=f"engine threads the run-time estimate assumes, as `axmpm run --threads`; {THREADS_DEFAULT}")

    sub.add_parser("schema", help="print the JSON Schema of scenario files")

    p = sub.add_parser("demo", help="granular column collapse a = 0.56 vs Lube et al. 2004 "
                       "(--column: 1D column vs its exact solution)")
    p.add_argument("--column", action="store_true",
                   help="the 1D column vs its exact solution (axisymmetric, linear MPM) instead")
    p.add_argument("--out", type=Path, default=Path("runs/demo"), help="output folder (default runs/demo)")
    p.add_argument("--overwrite", action="store_true", help="replace a non-empty folder that is not an axmpm run")
    p.add_argument("--threads", type=thread_count, default=0, help=THREADS_HELP)
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None)

    for module in _command_modules():
        module.add_parser(sub)
    return parser


#: Modules that each define one more command: ``NAME`` (the command), ``add_parser(sub)``
#: (adds its argparse sub-parser) and ``main(args) -> int`` (runs it, returns the exit code).
#: Adding a command = one new module + one line here.
COMMAND_MODULES: tuple[str, ...] = (
    "axmpm.run.resume",
    "axmpm.run.plot",
    "axmpm.cases.verify",
    "axmpm.bench",
    "axmpm.study.sweep",
    "axmpm.cases.validate",
    "axmpm.study.convergence",
    "axmpm.study.calibration",
)


def _command_modules() -> list:
    import importlib

    return [importlib.import_module(name) for name in COMMAND_MODULES]


def _cmd_check(args: argparse.Namespace) -> int:
    scenario = Scenario.from_toml(args.scenario, args.overrides)
    if args.print_resolved:
        print(scenario.to_toml(), end="")
    else:
        sim = scenario.simulation
        nx, ny = scenario.grid.cells()
        print(f"ok: {args.scenario} is valid: {sim.formulation}, {sim.shape_function}, "
              f"{scenario.particle_count()} particles, grid {nx} x {ny} cells, end_time {sim.end_time:g} s")
        if args.estimate:
            print(estimate_run(scenario, threads=args.threads).describe())
    return EXIT_OK


def _cmd_run(args: argparse.Namespace) -> int:
    scenario = Scenario.from_toml(args.scenario, args.overrides)
    summary = run(scenario, args.out, threads=args.threads, overwrite=args.overwrite, progress=args.progress)
    return report_run(summary, args.out)


def _cmd_schema(args: argparse.Namespace) -> int:
    print(schema_json())
    return EXIT_OK


def _cmd_demo(args: argparse.Namespace) -> int:
    if not args.column:
        print(f"Granular column collapse, a = 0.56, axisymmetric, {model_description()}, "
              "1 mm cells (30 per R_i), cpGIMP, pure FLIP")
        res = run_collapse_demo(args.out, overwrite=args.overwrite, threads=args.threads,
                                progress=args.progress)
        code = report_run(res.summary, res.out)
        if res.case is not None:
            c, lube = res.case, res.case["laws"]["lube2004"]
            print(f"runout (R_inf - R_i)/R_i, deposit one grain (1.15 mm) thick = {c['runout_normalised']:.3f} vs Lube et al. 2004 "
                  f"{lube['runout_normalised']:.3f} ({100 * lube['runout_normalised_rel_diff']:+.0f} %)")
            print(f"outermost particle of the deposit (R - R_i)/R_i = "
                  f"{c['runout_normalised_particle_edge']:.3f} "
                  f"({100 * c['runout_particle_edge_rel_diff']['lube2004']:+.0f} %)")
            print(f"final height H_inf/R_i = {c['final_height_normalised']:.3f} vs Lube et al. 2004 "
                  f"{lube['final_height_normalised']:.3f} ({100 * lube['final_height_rel_diff']:+.0f} %)")
            print(f"figures and summary: {res.figure}, {res.report}")
        return code

    print("1D column under self-weight, compression, rho0 g H / E = 0.01, axisymmetric, linear MPM")
    result = run_demo(args.out, overwrite=args.overwrite, threads=args.threads, progress=args.progress)
    code = report_run(result.summary, result.out)
    if result.errors is not None:
        e = result.errors
        print(f"vertical stress error vs exact: relative L2 {100 * e.stress_l2:.3f} %, "
              f"max {100 * e.stress_max:.3f} % of the base stress")
        print(f"vertical displacement error vs exact: relative L2 {100 * e.displacement_l2:.3f} %")
    return code


COMMANDS = {"run": _cmd_run, "check": _cmd_check, "schema": _cmd_schema, "demo": _cmd_demo}


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    commands = dict(COMMANDS)
    commands.update({m.NAME: m.main for m in _command_modules()})
    try:
        return commands[args.command](args)
    except ScenarioError as exc:
        print(exc.render(), file=sys.stderr)
        return EXIT_INPUT
    except RunError as exc:
        print(exc.render(), file=sys.stderr)
        return EXIT_INPUT
    except FileNotFoundError as exc:
        print(f"error: file not found: {exc.filename or exc}", file=sys.stderr)
        return EXIT_INPUT
    except OSError as exc:  # e.g. an output folder we may not write to
        where = f": {exc.filename}" if exc.filename else ""
        print(f"error: {exc.strerror or exc}{where}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
