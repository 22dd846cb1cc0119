"""Verification and validation cases behind one protocol, and their registry.

A *case* is a problem with a known answer (a closed form, an experiment, an empirical law):
it knows its runs, builds the scenario of each, reads its figures off a finished run folder,
compares them with the reference and writes a report. ``axmpm verify`` and ``axmpm validate``
run the selected cases through one generic driver (:mod:`axmpm.cases.driver`).

Adding a case = one module or sub-package in this folder that calls :func:`register` at import
(every module here is imported when the registry is first asked, so no other line changes)::

    from axmpm.cases import RunSpec, register

    class TaylorBar:
        name = "taylor_bar"
        kind = "verification"          # or "validation"
        title = "Taylor bar impact"
        default = False                # part of a plain `axmpm verify` (routine cost)?
        ...                            # the methods of Case below

    register(TaylorBar())

The protocol is :class:`Case`; the optional hooks the driver uses when a case
has them are listed in :class:`CaseHooks`.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

if TYPE_CHECKING:  # pragma: no cover
    from ..scenario import Scenario

__all__ = ["RunSpec", "Case", "CaseHooks", "KINDS", "register", "get", "all_cases", "default_cases",
           "names"]

#: The kinds of case; each has its command (``axmpm verify`` / ``axmpm validate``).
KINDS = ("verification", "validation")


@dataclass(frozen=True)
class RunSpec:
    """One run of a case."""

    name: str  # unique within the case; run folder DIR/cases/<case>/<name>/
    params: dict[str, Any]  # JSON-serialisable: scheme, formulation, cells, roughness, ...


@runtime_checkable
class Case(Protocol):
    """What every case implements. A result record, as the driver builds it, is
    ``{"case", "run", "name", **run.params, **metrics, "reference", "relative_error", "run_dir",
    "status", "message", ...}``."""

    name: str  # "column_1d", "column_collapse", "footing", "taylor_bar"
    kind: str  # "verification" | "validation"
    title: str

    def add_options(self, parser: argparse.ArgumentParser) -> None:
        """Case-specific CLI flags of ``axmpm verify``/``validate`` (the driver's own flags,
        ``--out --case --quick --jobs --threads --overwrite --set``, exist already)."""

    def runs(self, options: argparse.Namespace) -> list[RunSpec]:
        """The runs for these options (e.g. ``options.quick``)."""

    def scenario(self, run: RunSpec) -> "Scenario":
        """The scenario of a run (raises ScenarioError for bad input)."""

    def reference(self, run: RunSpec) -> dict[str, Any]:
        """The reference values of a run (closed form, law, experiment), by metric name."""

    def metrics(self, run: RunSpec, run_dir: Path) -> dict[str, Any]:
        """The figures of a run folder (called for failed runs too: return None values then)."""

    def checks(self, results: list[dict[str, Any]]) -> list[dict[str, Any]]:
        """Enforced criteria over the result records: ``{"name", "passed", "detail", ...}``."""

    def report(self, results: list[dict[str, Any]], out: Path) -> str:
        """Markdown section of ``DIR/report.md`` (figures written under ``out``, by convention
        ``out/"figures"``)."""


class CaseHooks:
    """Optional members the driver uses when a case has them (documentation only; a case need
    not inherit from this class).

    ``default: bool``
        Run by a plain ``axmpm verify``/``validate`` (no ``--case``): routine cost, part of the
        regular check. Absent = False, so a new case is opt-in.
    ``cost(run) -> float``
        Relative cost of a run; runs are started longest first (better load balance).
    ``progress(record) -> str``
        The text after ``[ i/n] case/run:`` in the progress line (default: the status).
    ``finish(results, out) -> None``
        Called once all runs are done, before ``checks``: figures that need several runs
        (e.g. comparing twins), ``passed`` flags, ...
    ``document(results, options) -> dict``
        Extra JSON for ``verification.json``/``validation.json`` (parameters, laws, ...; called
        after ``report``, which may leave what it wrote in ``results.context``); stored
        under ``case_data[name]``, and at the top level when this case ran alone.
    ``console(results, checks) -> str``
        Text printed to the terminal after the runs (e.g. a results table).
    ``handles_overrides: bool``
        True when ``runs`` reads ``options.overrides`` (``--set``) itself; otherwise the driver
        applies them as dotted overrides to every scenario of the case.
    ``matches(resolved: dict) -> bool``, ``sweep_columns: tuple[str, ...]``
        ``axmpm sweep`` adds the case's ``metrics`` columns ``sweep_columns`` to the rows of runs
        whose resolved scenario ``matches`` the case.
    """


_REGISTRY: dict[str, Case] = {}
_DISCOVERED = False


def register(case: Case) -> Case:
    """Add ``case`` to the registry (called by each case module at import); returns it."""
    missing = [m for m in ("name", "kind", "title", "add_options", "runs", "scenario", "reference",
                           "metrics", "checks", "report") if not hasattr(case, m)]
    if missing:
        raise TypeError(f"case {getattr(case, 'name', case)!r} lacks {', '.join(missing)}")
    if case.kind not in KINDS:
        raise ValueError(f"case {case.name!r}: kind must be one of {KINDS} (got {case.kind!r})")
    old = _REGISTRY.get(case.name)
    if old is not None and type(old) is not type(case):
        raise ValueError(f"two cases are named {case.name!r}: {type(old).__qualname__} and "
                         f"{type(case).__qualname__}")
    _REGISTRY[case.name] = case
    return case


def _discover() -> None:
    """Import every module and sub-package of this folder once (each registers its cases)."""
    global _DISCOVERED
    if _DISCOVERED:
        return
    _DISCOVERED = True
    for info in pkgutil.iter_modules(__path__):
        if not info.name.startswith("_"):
            importlib.import_module(f"{__name__}.{info.name}")


def get(name: str) -> Case:
    """The registered case ``name``; KeyError naming the known cases."""
    _discover()
    try:
        return _REGISTRY[name]
    except KeyError:
        raise KeyError(f"unknown case {name!r}; known: {', '.join(sorted(_REGISTRY))}") from None


def all_cases(kind: str | None = None) -> list[Case]:
    """Every registered case (of ``kind`` if given), sorted by name."""
    _discover()
    return [c for _, c in sorted(_REGISTRY.items()) if kind is None or c.kind == kind]


def default_cases(kind: str) -> list[Case]:
    """The cases a plain ``axmpm verify``/``validate`` runs: those with ``default = True``."""
    return [c for c in all_cases(kind) if getattr(c, "default", False)]


def names(kind: str | None = None) -> list[str]:
    return [c.name for c in all_cases(kind)]
