"""Parameter sweeps: the Cartesian product of scenario values, run on Dask.

``axmpm sweep SCENARIO.toml --param KEY=VALUES ... --out DIR`` runs one ordinary run folder
per combination under ``DIR/runs/`` and writes ``DIR/results.csv`` (one row per run: the
swept values, ``status``, ``error`` and the run's figures). See docs/sweeps.md.

Design:

* Every combination is validated in the driver (pydantic, cheap); an invalid one becomes a
  ``failed`` row with the validation message and is never submitted.
* Valid runs are submitted to a Dask cluster, one task per run; the task calls
  :func:`axmpm.run` on the worker, writes the run folder directly, and returns a small row.
  A task never raises for a failed run: engine failures, rejected scenarios and unexpected
  exceptions all become ``failed`` rows. A worker that dies under a run (a crash of the
  engine) surfaces as ``KilledWorker`` and is recorded the same way.
* The default cluster is a ``LocalCluster`` of *processes* (one single-threaded worker per
  run slot): the engine releases the GIL, so threads would work too, but a process
  isolates a run that crashes or leaks memory from the rest of the sweep.
* A run is skipped when its folder holds a completed run of the very same resolved
  scenario; missing, failed, interrupted or changed runs are (re)run.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import re
import sys
import time as _time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..cases import RunSpec as CaseRun, all_cases, get
from ..errors import RunError, ScenarioError
from ..run.output import is_completed_run
from ..run.parallel import open_client
from ..run.runner import run
from ..scenario import Scenario, apply_overrides, parse_value, read_toml

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = [
    "NAME",
    "add_parser",
    "main",
    "parse_param",
    "parse_values",
    "run_name",
    "RunSpec",
    "plan_sweep",
    "execute",
    "run_sweep",
    "SweepResult",
    "write_results",
    "read_results",
    "METRIC_COLUMNS",
    "case_columns",
]

NAME = "sweep"
RUNS = "runs"
RESULTS = "results.csv"
MANIFEST = "sweep.json"

#: Figures taken from a run's summary.json (energies flattened to their own columns).
METRIC_COLUMNS = [
    "steps",
    "end_time",
    "wall_seconds",
    "particle_steps_per_second",
    "particles",
    "stopped_at_rest",
    "kinetic_energy",
    "gravity_work",
]
#: Hidden row key: the case (``axmpm.cases``) whose ``metrics`` gave the row its extra columns.
CASE_KEY = "_case"


def case_columns(case_name: str | None) -> list[str]:
    """The extra columns of runs matched to the case ``case_name`` (its ``sweep_columns``)."""
    if not case_name:
        return []

    return list(getattr(get(case_name), "sweep_columns", ()))


# --------------------------------------------------------------------------- values


_NUMBER = r"[-+]?(?:\d[\d_]*\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_RANGE = re.compile(rf"^\s*(?:(log|lin):)?\s*({_NUMBER})\s*:\s*({_NUMBER})\s*:\s*({_NUMBER})\s*$")


def _num(text: str) -> int | float:
    text = text.strip().replace("_", "")
    try:
        return int(text)
    except ValueError:
        return float(text)


def _round(x: float, digits: int) -> float:
    """``x`` to ``digits`` significant digits (kills 0.30000000000000004 and friends)."""
    return float(f"{x:.{digits}g}")


def parse_values(text: str) -> list[Any]:
    """The values of one ``--param`` right-hand side.

    * ``V1,V2,...``: TOML values (``1``, ``2.5e6``, ``"a"``, ``[0.1, 0.2]``, ``true``); bare
      words are strings (``roller,fixed``), as with ``--set``.
    * ``START:STOP:STEP``: ``START, START+STEP, ...`` up to and including ``STOP`` (within
      1e-9 of a step); integers when all three are integers, else floats rounded to 12
      significant digits.
    * ``lin:START:STOP:N``: N evenly spaced values, both ends included.
    * ``log:START:STOP:N``: N log-spaced values, both ends included, rounded to 6
      significant digits (so folder names stay short); START, STOP > 0.
    """
    m = _RANGE.match(text)
    if m:
        kind, a, b, c = m.groups()
        start, stop = _num(a), _num(b)
        if kind in ("log", "lin"):
            n = _num(c)
            if not isinstance(n, int) or n < 1:
                raise ValueError(f"{kind}:START:STOP:N needs a whole number N >= 1 (got {c!r})")
            if n == 1:
                return [start]
            if kind == "lin":
                return [_round(start + (stop - start) * i / (n - 1), 12) for i in range(n)]
            if start <= 0 or stop <= 0:
                raise ValueError(f"log:START:STOP:N needs START > 0 and STOP > 0 (got {a}, {b})")
            la, lb = math.log(start), math.log(stop)
            return [_round(math.exp(la + (lb - la) * i / (n - 1)), 6) for i in range(n)]
        step = _num(c)
        if step == 0 or (stop - start) * step < 0:
            raise ValueError(f"START:STOP:STEP needs a non-zero STEP going from START towards STOP (got {text!r})")
        count = int(math.floor((stop - start) / step + 1e-9)) + 1
        if count > 100_000:
            raise ValueError(f"{text!r} gives {count} values; that is too many")
        if all(isinstance(v, int) for v in (start, stop, step)):
            return [start + i * step for i in range(count)]
        return [_round(start + i * step, 12) for i in range(count)]
    # A TOML array without its brackets: handles "1,2", "[0,1],[1,2]", '"a","b"'.
    try:
        values = tomllib.loads(f"v = [{text}]")["v"]
    except tomllib.TOMLDecodeError:
        values = [parse_value(part) for part in text.split(",")]
    if not values:
        raise ValueError("no values given")
    return values


def parse_param(item: str) -> tuple[str, list[Any]]:
    """``"materials.sand.friction_angle=20:30:5"`` → ``(key, [20, 25, 30])``; ScenarioError."""
    key, sep, raw = item.partition("=")
    key = key.strip()
    if not sep or not key or not raw.strip():
        raise ScenarioError([(key or item, f"--param must look like key.path=V1,V2,... or key.path=START:STOP:STEP (got {item!r})")], "--param")
    if any(not p for p in key.split(".")):
        raise ScenarioError([(key, "empty part in the dotted key")], "--param")
    try:
        values = parse_values(raw)
    except ValueError as exc:
        raise ScenarioError([(key, str(exc))], "--param") from None
    return key, values


# --------------------------------------------------------------------------- run names


_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]")
MAX_NAME = 150


def _format_value(value: Any) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        if value.is_integer() and abs(value) < 1e15:
            return str(int(value))
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "_".join(_format_value(v) for v in value)
    if isinstance(value, dict):
        return "_".join(f"{k}-{_format_value(v)}" for k, v in sorted(value.items()))
    return str(value)


def run_name(values: dict[str, Any]) -> str:
    """Folder name of a run: ``key=value`` pairs joined by ``__``, in the sweep's key order.

    Deterministic (a function of the keys and values only). Characters outside
    ``[A-Za-z0-9._+-]`` become ``-``; when that changed anything, or the name is longer
    than 150 characters, an 8-digit hash of the exact values keeps names unique.
    """
    if not values:
        return "base"
    pairs = [(k, _format_value(v)) for k, v in values.items()]
    raw = "__".join(f"{k}={v}" for k, v in pairs)
    safe = "__".join(f"{_UNSAFE.sub('-', k)}={_UNSAFE.sub('-', v)}" for k, v in pairs)
    if safe != raw or len(safe) > MAX_NAME:
        digest = hashlib.sha1(json.dumps(values, sort_keys=False, default=str).encode()).hexdigest()[:8]
        safe = safe[: MAX_NAME - 9] + "-" + digest
    return safe


# --------------------------------------------------------------------------- planning


@dataclass
class RunSpec:
    """One run of a sweep: its name, swept values, and raw scenario data (overrides applied)."""

    name: str
    values: dict[str, Any]
    data: dict[str, Any] | None = None  # raw scenario data (None when invalid)
    error: str = ""  # validation message when the combination is invalid
    resolved: dict[str, Any] | None = None  # Scenario.to_dict() when valid
    case: str | None = None  # the case (axmpm.cases) the scenario matches: its metrics become columns


def _override_text(key: str, value: Any) -> str:
    import tomli_w

    return key + "=" + tomli_w.dumps({"v": value}).partition("=")[2].strip()


def matching_case(resolved: dict[str, Any]) -> str | None:
    """The first registered case whose ``matches(resolved)`` is true and that has
    ``sweep_columns`` (e.g. a column collapse: some wall has a removal time), or None."""
    for case in all_cases():
        matches = getattr(case, "matches", None)
        if matches is not None and getattr(case, "sweep_columns", None) and matches(resolved):
            return case.name
    return None


def _validation_message(exc: ScenarioError) -> str:
    return "; ".join(f"{k}: {m}" if k else m for k, m in exc.errors)


def plan_runs(
    base: dict[str, Any],
    combos: Iterable[dict[str, Any]],
    overrides: Sequence[str] = (),
    names: Iterable[str] | None = None,
) -> list[RunSpec]:
    """RunSpecs of ``combos`` (key → value) applied to the raw scenario data ``base``
    after the ``--set`` ``overrides``; each is validated, an invalid one carries its error."""
    data0 = apply_overrides(base, list(overrides)) if overrides else base
    specs: list[RunSpec] = []
    names_iter = iter(names) if names is not None else None
    seen: dict[str, dict[str, Any]] = {}
    for values in combos:
        name = next(names_iter) if names_iter is not None else run_name(values)
        if name in seen:
            raise ScenarioError([("--param", f"two runs would share the folder {name!r}: {seen[name]} and {values}")])
        seen[name] = values
        spec = RunSpec(name=name, values=dict(values))
        try:
            data = apply_overrides(data0, [_override_text(k, v) for k, v in values.items()])
            scenario = Scenario.from_dict(data)
        except ScenarioError as exc:
            spec.error = _validation_message(exc)
        else:
            spec.data = data
            spec.resolved = scenario.to_dict()
            spec.case = matching_case(spec.resolved)
        specs.append(spec)
    return specs


def plan_sweep(
    scenario: str | Path | dict[str, Any],
    params: dict[str, list[Any]] | Sequence[tuple[str, list[Any]]],
    overrides: Sequence[str] = (),
) -> list[RunSpec]:
    """RunSpecs of the Cartesian product of ``params`` (first key varies slowest)."""
    base = read_toml(scenario) if not isinstance(scenario, dict) else scenario
    items = list(params.items()) if isinstance(params, dict) else list(params)
    keys = [k for k, _ in items]
    dup = {k for k in keys if keys.count(k) > 1}
    if dup:
        raise ScenarioError([(k, "given more than once with --param") for k in sorted(dup)], "--param")
    combos = [dict(zip(keys, combo)) for combo in itertools.product(*(v for _, v in items))]
    return plan_runs(base, combos, overrides)


# --------------------------------------------------------------------------- the task


def _flatten_summary(summary: dict[str, Any]) -> dict[str, Any]:
    row = {k: summary.get(k, "") for k in METRIC_COLUMNS if k in summary}
    for k, v in (summary.get("energies") or {}).items():
        row[k] = v
    return row


def _case_metrics(case_name: str, run_dir: Path) -> tuple[dict[str, Any], str]:
    """The ``sweep_columns`` of ``case.metrics`` on a run folder (blank, with a note, on error)."""
    try:
        case = get(case_name)
        metrics = dict(case.metrics(CaseRun(run_dir.name, {}), run_dir))
    except Exception as exc:  # leave the columns blank, say why
        return {}, f"{case_name} metrics: {type(exc).__name__}: {exc}"
    return {k: metrics[k] for k in case_columns(case_name) if k in metrics}, ""


def metrics_of(run_dir: Path, case: str | None) -> dict[str, Any]:
    """The row figures of a finished run folder (summary, and the case's metrics when ``case``)."""
    return _row_from_summary(json.loads((run_dir / "summary.json").read_text()), run_dir, case)


def _row_from_summary(summary: dict[str, Any], run_dir: Path, case: str | None) -> dict[str, Any]:
    """Status, error, the summary's figures and (for a completed run matching a case) the case's
    metrics."""
    completed = summary.get("status") == "completed"
    row: dict[str, Any] = {"status": "completed" if completed else "failed",
                           "error": "" if completed else summary.get("message", "")}
    row.update(_flatten_summary(summary))
    if case and completed:
        row[CASE_KEY] = case
        values, note = _case_metrics(case, run_dir)
        row.update(values)
        if note:
            row["metrics_note"] = note
    return row


def run_task(data: dict[str, Any], out: str, threads: int, case: str | None) -> dict[str, Any]:
    """Run one scenario into ``out`` on a worker; never raises for a failed run."""
    out_path = Path(out)
    started = _time.perf_counter()
    try:
        scenario = Scenario.from_dict(data)
        summary = run(scenario, out_path, threads=threads, overwrite=True, progress=False)
    except ScenarioError as exc:
        return {"status": "failed", "error": _validation_message(exc)}
    except RunError as exc:
        return {"status": "failed", "error": str(exc), "wall_seconds": _time.perf_counter() - started}
    except Exception as exc:  # a bug or I/O problem: record it, keep the sweep going
        return {"status": "failed", "error": f"{type(exc).__name__}: {exc}",
                "wall_seconds": _time.perf_counter() - started}
    return _row_from_summary(summary, out_path, case)


# --------------------------------------------------------------------------- execution


@dataclass
class SweepResult:
    """What :func:`execute` did: the rows (in plan order) and the counts."""

    rows: list[dict[str, Any]]
    keys: list[str]
    submitted: int = 0
    skipped: int = 0
    invalid: int = 0
    results_path: Path | None = None

    @property
    def failed(self) -> int:
        return sum(1 for r in self.rows if r.get("status") != "completed")

    @property
    def completed(self) -> int:
        return sum(1 for r in self.rows if r.get("status") == "completed")


def _row(spec: RunSpec, result: dict[str, Any]) -> dict[str, Any]:
    return {"run": spec.name, **spec.values, **result}


def execute(
    specs: Sequence[RunSpec],
    out: str | Path,
    client: Any = None,
    threads_per_run: int = 1,
    progress: bool | None = None,
    keys: Sequence[str] | None = None,
    log: Callable[[str], None] | None = print,
    description: str = "sweep",
    connect: Callable[[], Any] | None = None,
) -> SweepResult:
    """Run the ``specs`` on ``client`` into ``out/runs/<name>`` and write ``out/results.csv``
    (rewritten after every finished run, so an interrupted sweep keeps what it did).

    Without ``client``, ``connect()`` (a context manager factory, default
    :func:`open_client` with ``threads_per_run``) is entered only when something must run.
    """
    from distributed import as_completed
    from tqdm import tqdm

    out = Path(out).resolve()
    runs_dir = out / RUNS
    runs_dir.mkdir(parents=True, exist_ok=True)
    keys = list(keys) if keys is not None else list(dict.fromkeys(k for s in specs for k in s.values))
    rows: list[dict[str, Any] | None] = [None] * len(specs)
    result = SweepResult(rows=[], keys=keys, results_path=out / RESULTS)

    todo: list[int] = []
    for i, spec in enumerate(specs):
        if spec.data is None:
            rows[i] = _row(spec, {"status": "failed", "error": spec.error})
            result.invalid += 1
        elif is_completed_run(runs_dir / spec.name, spec.resolved or {}):
            rows[i] = _row(spec, metrics_of(runs_dir / spec.name, spec.case))
            result.skipped += 1
        else:
            todo.append(i)
    result.submitted = len(todo)

    def flush() -> None:
        write_results(out / RESULTS, [r for r in rows if r is not None], keys)

    if log:
        parts = [f"{len(specs)} runs", f"{len(todo)} to run"]
        if result.skipped:
            parts.append(f"skipped {result.skipped} already completed")
        if result.invalid:
            parts.append(f"{result.invalid} invalid")
        log(f"{description}: " + ", ".join(parts))
    flush()

    if todo and client is None:
        factory = connect or (lambda: open_client(threads_per_run=threads_per_run))
        with factory() as c:
            return execute(specs, out, c, threads_per_run, progress, keys, None, description)
    if todo:
        futures = {}
        for i in todo:
            spec = specs[i]
            fut = client.submit(
                run_task, spec.data, str(runs_dir / spec.name), int(threads_per_run), spec.case,
                pure=False, key=f"axmpm-{_key_token(spec.name)}-{os.urandom(4).hex()}",
            )
            futures[fut] = i
        disable = not (sys.stderr.isatty() if progress is None else progress)
        failed = 0
        bar = tqdm(total=len(todo), desc=description, unit="run", file=sys.stderr, disable=disable)
        try:
            for fut in as_completed(futures):
                i = futures[fut]
                try:
                    res = fut.result()
                except Exception as exc:  # KilledWorker, CancelledError, lost connection
                    res = {"status": "failed", "error": f"{type(exc).__name__}: {exc}"}
                rows[i] = _row(specs[i], res)
                if res.get("status") != "completed":
                    failed += 1
                bar.set_postfix_str(f"failed {failed}", refresh=False)
                bar.update(1)
                flush()
        except KeyboardInterrupt:
            client.cancel(list(futures))
            raise
        finally:
            bar.close()
    result.rows = [r for r in rows if r is not None]
    flush()
    return result


def _key_token(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.=-]", "-", name)[:60]


# --------------------------------------------------------------------------- results.csv


def _columns(rows: Sequence[dict[str, Any]], keys: Sequence[str]) -> list[str]:
    cols = ["run", *keys, "status", "error"]
    present = {k for r in rows for k in r}
    cols += [c for c in METRIC_COLUMNS if c in present]
    cases = list(dict.fromkeys(r[CASE_KEY] for r in rows if r.get(CASE_KEY)))
    case_cols = list(dict.fromkeys(c for name in cases for c in case_columns(name)))
    extra = sorted(present - set(cols) - set(case_cols) - {"metrics_note", CASE_KEY})
    cols += extra  # other energies, if the engine reports more
    if any(r.get(c) not in (None, "") for r in rows for c in case_cols) or any("metrics_note" in r for r in rows):
        cols += case_cols + ["metrics_note"]
    return cols


def _cell(value: Any) -> Any:
    if value is None:
        return ""
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value)
    if isinstance(value, float):
        return repr(value)
    return value


def write_results(path: Path, rows: Sequence[dict[str, Any]], keys: Sequence[str]) -> None:
    """Write ``results.csv`` atomically (temporary file, then ``os.replace``)."""
    cols = _columns(rows, keys)
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(cols)
        for r in rows:
            writer.writerow([_cell(r.get(c)) for c in cols])
    os.replace(tmp, path)


def read_results(path: str | Path) -> list[dict[str, Any]]:
    """``results.csv`` back as dicts; numbers as numbers, blanks as None."""
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        rows = []
        for raw in reader:
            row: dict[str, Any] = {}
            for k, v in raw.items():
                if k in ("run", "status", "error", "metrics_note"):
                    row[k] = v
                elif v == "":
                    row[k] = None
                else:
                    try:
                        row[k] = tomllib.loads("v = " + v)["v"]
                    except tomllib.TOMLDecodeError:
                        try:
                            row[k] = json.loads(v)
                        except ValueError:
                            row[k] = v
            rows.append(row)
    return rows


# --------------------------------------------------------------------------- high level


def run_sweep(
    scenario: str | Path,
    params: dict[str, list[Any]] | Sequence[tuple[str, list[Any]]],
    out: str | Path,
    overrides: Sequence[str] = (),
    *,
    client: Any = None,
    scheduler: str | None = None,
    workers: int | None = None,
    threads_per_run: int = 1,
    processes: bool = True,
    progress: bool | None = None,
    log: Callable[[str], None] | None = print,
) -> SweepResult:
    """Plan and run a sweep; use ``client`` if given, else open one (see :func:`open_client`)."""
    specs = plan_sweep(scenario, params, overrides)
    keys = [k for k, _ in (params.items() if isinstance(params, dict) else params)]
    out = Path(out)
    _check_out(out)
    out.mkdir(parents=True, exist_ok=True)
    manifest = {
        "program": "axmpm",
        "command": "sweep",
        "scenario": str(Path(scenario).resolve()),
        "params": {k: v for k, v in (params.items() if isinstance(params, dict) else params)},
        "set": list(overrides),
    }
    (out / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n")
    return execute(specs, out, client, threads_per_run, progress, keys, log,
                   connect=lambda: open_client(scheduler, workers, threads_per_run, processes))


def _check_out(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise RunError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not ((out / MANIFEST).exists() or (out / RESULTS).exists()
                                                    or (out / RUNS).is_dir()):
        raise RunError(f"--out {out} is a non-empty folder that is not an axmpm sweep; choose another folder")


# --------------------------------------------------------------------------- CLI


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        NAME,
        help="run a scenario over the Cartesian product of parameter values (Dask)",
        description="Run the Cartesian product of --param values, one run folder per combination "
        "under OUT/runs/, a results table in OUT/results.csv. Calling it again with the same --out "
        "runs only what is missing, failed or changed.",
    )
    p.add_argument("scenario", type=Path, help="scenario TOML file")
    p.add_argument("--param", dest="params", action="append", default=[], required=True,
                   metavar="KEY=VALUES",
                   help="a swept dotted key: KEY=V1,V2,... (TOML values), KEY=START:STOP:STEP "
                   "(STOP included), KEY=lin:START:STOP:N or KEY=log:START:STOP:N (repeatable)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scenario value for every run (repeatable)")
    p.add_argument("--out", type=Path, required=True, help="sweep folder")
    p.add_argument("--workers", type=int, default=0,
                   help="local worker processes, 0 = cores / threads-per-run (default)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="use an existing Dask cluster, e.g. tcp://host:8786 (workers must see --out)")
    p.add_argument("--threads-per-run", type=int, default=1, help="engine threads of each run (default 1)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="show a progress bar (default: when stderr is a terminal)")


def report(result: SweepResult, out: Path) -> None:
    print(f"done: {result.completed} completed, {result.failed} failed "
          f"({result.submitted} run now, {result.skipped} skipped); results in {out / RESULTS}")
    for r in result.rows:
        if r.get("status") != "completed":
            print(f"failed: {r['run']}: {r.get('error', '')}", file=sys.stderr)


def main(args: argparse.Namespace) -> int:
    params = [parse_param(p) for p in args.params]
    if args.threads_per_run < 1:
        raise RunError("--threads-per-run must be >= 1")
    result = run_sweep(
        args.scenario, params, args.out, args.overrides,
        scheduler=args.scheduler, workers=args.workers or None,
        threads_per_run=args.threads_per_run, progress=args.progress,
    )
    report(result, args.out)
    return 0 if result.failed == 0 else 3
