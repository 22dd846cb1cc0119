"""The generic driver of ``axmpm verify`` and ``axmpm validate``: runs the selected cases.

For every selected case and every run of ``case.runs(options)``:

1. ``case.scenario(run)`` (all of them first, so bad input stops everything with exit 2
   before anything runs);
2. the scenario runs into ``DIR/cases/<case>/<run>/`` (one engine thread per run by default,
   runs in parallel processes, the longest first); a failed simulation is a result, not a crash;
3. ``case.metrics(run, run_dir)`` and ``case.reference(run)``; the record gets the relative
   error ``(metric − reference)/reference`` of every numeric metric that has a reference;
4. once all runs are done: ``case.finish(results, out)`` (optional), ``case.checks(results)``,
   ``case.report(results, out)``.

Writes ``DIR/verification.json`` (``validation.json``) and ``DIR/report.md``; the exit code is 0
when every check passes and 1 otherwise. The record layout and the optional hooks are described
in :mod:`axmpm.cases`.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import RunError
from ..run.output import is_completed_run
from ..run.parallel import available_cores, open_client, process_pool
from ..run.runner import run as run_scenario
from ..scenario import Scenario, apply_overrides
from . import Case, RunSpec, all_cases, default_cases, get

__all__ = ["COMMANDS", "Results", "run_cases", "execute_run", "relative_errors", "select", "add_parser",
           "main", "shared_setting", "CASES", "REPORT"]

CASES = "cases"
REPORT = "report.md"

#: kind → (command, results file, default output folder, help)
COMMANDS: dict[str, tuple[str, str, str, str]] = {
    "verification": ("verify", "verification.json", "runs/verify",
                     "verification cases against closed-form solutions, with a report"),
    "validation": ("validate", "validation.json", "runs/validate",
                   "validation cases against experiments and empirical laws, with a report"),
}


class Results(list):
    """The result records of one case (a list), with ``context``: what the driver knows about the
    whole invocation (``quick``, ``jobs``, ``threads_per_run``, ``wall_seconds``, ``options``)."""

    def __init__(self, records: Sequence[dict[str, Any]] = (), context: dict[str, Any] | None = None):
        super().__init__(records)
        self.context: dict[str, Any] = dict(context or {})


def run_dir_of(case: Case | str, run: RunSpec | str) -> str:
    """A run's folder relative to the output folder: ``cases/<case>/<run>``."""
    case_name = case if isinstance(case, str) else case.name
    run_name = run if isinstance(run, str) else run.name
    return f"{CASES}/{case_name}/{run_name}"


def relative_errors(metrics: dict[str, Any], reference: dict[str, Any]) -> dict[str, float | None]:
    """(metric − reference)/reference for every key of ``reference`` (None where either is not a
    finite number or the reference is zero)."""
    out: dict[str, float | None] = {}
    for key, ref in reference.items():
        value = metrics.get(key)
        ok = all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in (value, ref))
        out[key] = (value - ref) / ref if ok and ref != 0 else None
    return out


def build_scenario(case: Case, run: RunSpec, overrides: Sequence[str] = ()) -> Any:
    """``case.scenario(run)`` with the ``--set`` items applied as dotted overrides, unless the case
    takes them itself (``handles_overrides = True``, e.g. as builder parameters)."""
    scenario = case.scenario(run)
    if overrides and not getattr(case, "handles_overrides", False):
        scenario = Scenario.from_dict(apply_overrides(scenario.to_dict(), list(overrides)),
                                      source=f"{case.name}/{run.name}")
    return scenario


def execute_run(case_name: str, run: RunSpec, out: str | Path, threads: int = 1,
                overrides: Sequence[str] = (), reuse: bool = False) -> dict[str, Any]:
    """Run one run of a case into ``out/cases/<case>/<run>`` and build its record. Never raises for
    a failing simulation or analysis: the record then has status "failed" and the message.
    ``reuse``: a folder that holds a completed run of the very same resolved scenario is not run
    again (resumable sweeps); the record then has ``reused = True``."""
    case = get(case_name)
    rel = run_dir_of(case, run)
    run_dir = Path(out) / rel
    record: dict[str, Any] = {"case": case.name, "run": run.name, "name": run.name, **run.params,
                              "run_dir": rel, "status": "not run", "message": ""}
    started = time.perf_counter()
    try:
        scenario = build_scenario(case, run, overrides)
        # The resolved setting (the case's own or a --set override), for the case's documentation.
        record["flip_fraction"] = scenario.simulation.flip_fraction
        if reuse and _completed(run_dir, scenario):
            summary = json.loads((run_dir / "summary.json").read_text())
            record["reused"] = True
        else:
            summary = run_scenario(scenario, run_dir, threads=threads, overwrite=True, progress=False)
        record.update(status=summary["status"], message=summary["message"], particles=summary["particles"],
                      steps=summary["steps"],
                      final_kinetic_energy=summary.get("energies", {}).get("kinetic_energy"))
    except Exception as exc:  # noqa: BLE001 - a broken run is recorded, the others still run
        record.update(status="failed", message=f"{type(exc).__name__}: {exc}")
    record["wall_seconds"] = time.perf_counter() - started
    status, message = record["status"], record["message"]
    metrics: dict[str, Any] = {}
    try:
        metrics = dict(case.metrics(run, run_dir))
    except Exception as exc:  # noqa: BLE001
        if status == "completed":
            status, message = "failed", f"metrics: {type(exc).__name__}: {exc}"
    record.update(metrics)
    try:
        reference = dict(case.reference(run))
    except Exception as exc:  # noqa: BLE001
        reference = {}
        message = (message + "; " if message else "") + f"reference: {type(exc).__name__}: {exc}"
    record.update(reference=reference, relative_error=relative_errors(metrics, reference),
                  status=status, message=message)
    return record


def shared_setting(results: Sequence[dict[str, Any]], key: str) -> Any:
    """The value of ``key`` in the records that have it: one value when they all agree, else the
    sorted distinct values (None when no record has it), for a case's ``document``."""
    values = sorted({r[key] for r in results if r.get(key) is not None})
    return values[0] if len(values) == 1 else (values or None)


def _completed(run_dir: Path, scenario: Any) -> bool:
    """``run_dir`` holds a completed run of exactly ``scenario`` (resolved)."""
    return is_completed_run(run_dir, scenario.to_dict())


def _progress_text(case: Case, record: dict[str, Any]) -> str:
    hook = getattr(case, "progress", None)
    if hook is not None:
        return hook(record)
    return record["status"] + (f": {record['message']}" if record.get("message") else "")


def run_cases(cases: Sequence[Case], options: argparse.Namespace, out: Path, jobs: int = 1,
              threads: int = 1, log: Any = sys.stdout) -> dict[str, Results]:
    """Run every run of ``cases`` into ``out`` (a process pool when ``jobs`` > 1); the records of
    each case in the order of its ``runs``. The scenarios are all built first (ScenarioError)."""
    plan: list[tuple[Case, RunSpec]] = []
    for case in cases:
        runs = list(case.runs(options))
        names = [r.name for r in runs]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"case {case.name}: duplicate run names {dup}")
        plan += [(case, r) for r in runs]
    overrides = list(getattr(options, "overrides", None) or [])
    for case, r in plan:  # bad input stops everything before anything runs
        build_scenario(case, r, overrides)
    done: dict[tuple[str, str], dict[str, Any]] = {}
    total = len(plan)

    def finished(case: Case, record: dict[str, Any]) -> None:
        done[(case.name, record["run"])] = record
        if log is not None:
            print(f"[{len(done):3d}/{total}] {case.name}/{record['run']}: {_progress_text(case, record)} "
                  f"({record['wall_seconds']:.1f} s)", file=log, flush=True)

    def cost(item: tuple[Case, RunSpec]) -> float:
        hook = getattr(item[0], "cost", None)
        return float(hook(item[1])) if hook is not None else 1.0

    order = sorted(plan, key=cost, reverse=True)  # longest first: better load balance
    if any(_resumable(case, options) for case in cases):
        _run_on_dask(order, options, out, jobs, threads, overrides, finished)
    elif jobs <= 1 or total <= 1:
        for case, r in order:
            finished(case, execute_run(case.name, r, out, threads, overrides))
    else:
        from concurrent.futures import as_completed

        with process_pool(min(jobs, total)) as pool:
            futures = {pool.submit(execute_run, case.name, r, str(out), threads, overrides): case for case, r in order}
            for future in as_completed(futures):
                finished(futures[future], future.result())
    return {case.name: Results([done[(case.name, r.name)] for c, r in plan if c is case]) for case in cases}


def _resumable(case: Case, options: argparse.Namespace) -> bool:
    """The case asks for a resumable sweep on Dask (optional hook ``resumable(options)``)."""
    hook = getattr(case, "resumable", None)
    return bool(hook(options)) if hook is not None else False


def _run_on_dask(order: Sequence[tuple[Case, RunSpec]], options: argparse.Namespace, out: Path, jobs: int,
                 threads: int, overrides: Sequence[str], finished: Any) -> None:
    """Resumable sweeps (``axmpm validate --case column_collapse --aspect-ratios ...``): every run is
    one Dask task (:func:`axmpm.run.parallel.open_client`: ``--scheduler ADDRESS`` or a local
    cluster of ``--workers`` single-threaded processes); a completed run of the same scenario is
    reused, a failing or crashing run is a failed record and the others go on."""
    todo = []
    for case, r in order:  # completed runs: no cluster needed
        record = execute_run(case.name, r, out, threads, overrides, reuse=True) if _completed_quick(case, r, out, overrides) else None
        if record is not None:
            finished(case, record)
        else:
            todo.append((case, r))
    if not todo:
        return
    from distributed import as_completed

    workers = getattr(options, "workers", None) or jobs
    with open_client(scheduler=getattr(options, "scheduler", None), workers=min(int(workers), len(todo)),
                     threads_per_run=threads) as client:
        futures = {client.submit(execute_run, case.name, r, str(out), threads, list(overrides), True, pure=False,
                                 key=f"axmpm-{case.name}-{r.name}-{os.urandom(4).hex()}"): (case, r)
                   for case, r in todo}
        for future in as_completed(futures):
            case, r = futures[future]
            try:
                record = future.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker (engine crash), lost connection
                record = {"case": case.name, "run": r.name, "name": r.name, **r.params,
                          "run_dir": run_dir_of(case, r), "status": "failed",
                          "message": f"{type(exc).__name__}: {exc}", "wall_seconds": 0.0}
            finished(case, record)


def _completed_quick(case: Case, run: RunSpec, out: Path, overrides: Sequence[str]) -> bool:
    try:
        return _completed(Path(out) / run_dir_of(case, run), build_scenario(case, run, overrides))
    except Exception:  # noqa: BLE001
        return False


# --------------------------------------------------------------------------- command


def select(kind: str, names: Sequence[str] | None) -> list[Case]:
    """The cases ``--case`` names (each may be comma-separated), or the default ones of ``kind``."""
    if not names:
        cases = default_cases(kind)
        if not cases:
            raise RunError(f"no default {kind} case is registered; name one with --case")
        return cases
    wanted = [n.strip() for item in names for n in item.split(",") if n.strip()]
    known = {c.name: c for c in all_cases(kind)}
    unknown = [n for n in wanted if n not in known]
    if unknown:
        raise RunError(f"--case: unknown {kind} case(s) {', '.join(unknown)}; known: {', '.join(known)}")
    return [known[n] for n in dict.fromkeys(wanted)]


def _prepare(out: Path, results_file: str, command: str, cases: Sequence[Case], overwrite: bool,
             keep: Sequence[str] = ()) -> None:
    """Refuse a file or a non-empty folder that is not an output of this command (unless
    ``overwrite``: it is then emptied); clear the run folders of the selected cases."""
    if out.exists() and not out.is_dir():
        raise RunError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()):
        ours = (out / results_file).exists() or (out / CASES).is_dir()
        if not (ours or overwrite):
            raise RunError(f"--out {out} is a non-empty folder that is not an axmpm {command} output; "
                           "choose another folder or pass --overwrite")
        resolved = out.resolve()
        if resolved in {Path("/").resolve(), Path.home().resolve()} or Path.cwd().resolve().is_relative_to(resolved):
            raise RunError(f"refusing to clear {out}: it is the root, home or current folder")
        targets = list(out.iterdir()) if not ours else [out / CASES / c.name for c in cases if c.name not in keep]
        for child in targets:
            if child.is_dir() and not child.is_symlink():
                shutil.rmtree(child)
            elif child.exists() or child.is_symlink():
                child.unlink()
    out.mkdir(parents=True, exist_ok=True)


def _write_json(path: Path, data: dict[str, Any]) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=2, allow_nan=False, default=_jsonable) + "\n")
    os.replace(tmp, path)


def _jsonable(value: Any) -> Any:
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "item"):  # numpy scalars
        return value.item()
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def _finite(value: Any) -> Any:
    """JSON has no NaN: NaN and inf become None (recursively)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def verify_or_validate(kind: str, cases: Sequence[Case], options: argparse.Namespace, out: str | Path, *,
                       jobs: int | None = None, threads: int = 1, overwrite: bool = False,
                       log: Any = sys.stdout) -> dict[str, Any]:
    """Run ``cases`` (all of ``kind``) into ``out``; write the results JSON and ``report.md``;
    return the JSON data (``passed`` true when every check passes)."""
    command, results_file, _, _ = COMMANDS[kind]
    out = Path(out)
    _prepare(out, results_file, command, cases, overwrite,
             keep=[c.name for c in cases if _resumable(c, options)])
    jobs = available_cores() if not jobs else int(jobs)
    started = time.perf_counter()
    by_case = run_cases(cases, options, out, jobs=jobs, threads=threads, log=log)
    context = {"quick": bool(getattr(options, "quick", False)), "jobs": jobs, "threads_per_run": threads,
               "wall_seconds": time.perf_counter() - started, "options": vars(options),
               "figures": bool(getattr(options, "figures", True))}
    records: list[dict[str, Any]] = []
    checks: list[dict[str, Any]] = []
    case_data: dict[str, Any] = {}
    reports: list[str] = []
    for case in cases:
        results = by_case[case.name]
        results.context = dict(context)
        finish = getattr(case, "finish", None)
        if finish is not None:
            finish(results, out)
        case_checks = [dict(c, case=case.name) for c in case.checks(results)]
        for c in case_checks:
            c.setdefault("detail", "")
            c["passed"] = bool(c.get("passed"))
            # A check with required = False is an aim (a target beyond the enforced limit): it is
            # reported, but missing it does not fail the run's exit code.
            c["required"] = bool(c.get("required", True))
        results.context["checks"] = case_checks
        reports.append(case.report(results, out))
        document = getattr(case, "document", None)
        case_data[case.name] = {"title": case.title, **(document(results, options) if document else {})}
        records += results
        checks += case_checks
    data: dict[str, Any] = {
        "program": f"axmpm {command}",
        "kind": kind,
        "selected": [c.name for c in cases],
        **({k: v for k, v in case_data[cases[0].name].items() if k != "title"} if len(cases) == 1 else {}),
        "quick": context["quick"],
        "jobs": jobs,
        "threads_per_run": threads,
        "wall_seconds": context["wall_seconds"],
        "passed": all(c["passed"] for c in checks if c["required"]),
        "targets_met": all(c["passed"] for c in checks),
        "cases": records,
        "checks": checks,
        "case_data": case_data,
    }
    _write_json(out / results_file, _finite(data))
    if len(reports) == 1:
        text = reports[0]
    else:
        text = f"# axmpm {command}: {', '.join(c.name for c in cases)}\n\n" + "\n\n".join(reports)
    (out / REPORT).write_text(text)
    data["by_case"] = by_case
    return data


def add_parser(sub: Any, kind: str) -> argparse.ArgumentParser:
    """The sub-command of ``kind``: the driver's flags, then every case's ``add_options``."""
    command, results_file, default_out, help_text = COMMANDS[kind]
    defaults = [c.name for c in default_cases(kind)]
    known = [c.name for c in all_cases(kind)]
    p = sub.add_parser(command, help=help_text, conflict_handler="resolve",
                       description=f"Run {kind} cases (default: {', '.join(defaults) or 'none'}; "
                       f"known: {', '.join(known)}); write DIR/{results_file} and DIR/{REPORT}. "
                       "Exit code 1 when an enforced check fails (aims are reported, not enforced).")
    p.add_argument("--case", dest="case", action="append", default=None, metavar="NAME",
                   help=f"case to run (repeatable or comma-separated; default: {', '.join(defaults) or 'none'})")
    p.add_argument("--out", type=Path, default=Path(default_out), help=f"output folder (default {default_out})")
    p.add_argument("--quick", action="store_true", help="the cases' quick variants (coarser grids), where they have one")
    p.add_argument("--jobs", type=int, default=0, help="runs in parallel, 0 = one per core (default)")
    p.add_argument("--threads", type=int, default=1, help="engine threads per run (default 1)")
    p.add_argument("--overwrite", action="store_true",
                   help=f"replace a non-empty folder that is not an axmpm {command} output")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override in every run: a dotted scenario key (simulation.cfl=0.3); column_collapse "
                   "also takes its builder's parameters (cell_size=0.004, friction_coefficient=0.45, material_model=mohr_coulomb, end_time=0.1, ...)")
    for case in all_cases(kind):
        case.add_options(p)
    return p


def failed_and_missed(checks: list[dict[str, Any]]) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The enforced checks that failed (exit code 1) and the aims (``required = False``) missed."""
    failed = [c for c in checks if not c["passed"] and c.get("required", True)]
    missed = [c for c in checks if not c["passed"] and not c.get("required", True)]
    return failed, missed


def main(args: argparse.Namespace, kind: str) -> int:
    command, results_file, _, _ = COMMANDS[kind]
    cases = select(kind, args.case)
    quick = bool(getattr(args, "quick", False))
    print(f"axmpm {command}: {'quick' if quick else 'full'} run of {', '.join(c.name for c in cases)} "
          f"into {args.out}", flush=True)
    data = verify_or_validate(kind, cases, args, args.out, jobs=args.jobs, threads=max(1, args.threads),
                              overwrite=args.overwrite)
    for case in cases:
        console = getattr(case, "console", None)
        if console is not None:
            text = console(data["by_case"][case.name], [c for c in data["checks"] if c["case"] == case.name])
            if text:
                print(text)
    failed, missed = failed_and_missed(data["checks"])
    for label, group in (("FAIL", failed), ("MISSED (aim, not enforced)", missed)):
        for c in group:
            detail = c.get("detail") or ""
            print(f"{label}: {c['case']}: {c['name']}" + (f": {detail}" if detail else ""))
    print(f"{len(data['checks']) - len(failed) - len(missed)}/{len(data['checks'])} checks pass"
          + (f" ({len(missed)} aim(s) missed)" if missed else "")
          + f"; {data['wall_seconds']:.1f} s; {results_file} and report: {Path(args.out) / REPORT}")
    return 0 if not failed else 1
