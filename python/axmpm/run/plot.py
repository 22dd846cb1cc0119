"""``axmpm plot RUN [COLUMN ...]``: columns of a run's ``history.csv`` drawn as a PNG, against
time or against another column.

Examples::

    axmpm plot runs/block                       # the energy columns against time
    axmpm plot runs/block bottom.force_y        # the reaction on the base against time
    axmpm plot runs/footing footing.force_y --x footing.displacement_y --negate-x
                                                # load against settlement

y points up, so a settlement is a negative ``displacement_y``; ``--negate-x`` and
``--negate-y`` plot the negative of the abscissa or of the ordinates. Values are drawn as
recorded, one point per row: a force is the mean force the material exerted on the constraint
or body since the previous row (N; axisymmetric: whole body, plane strain: per metre).
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import RunError
from ..plotting import pyplot, save_figure
from .output import HISTORY, load_run

__all__ = ["NAME", "add_parser", "main", "energy_columns", "history_figure", "plot_history"]

NAME = "plot"

#: Columns of history.csv that are neither an energy nor a constraint's or body's quantity.
BOOKKEEPING = ("time", "steps", "dt", "wall_seconds", "water_outflow")


def energy_columns(columns: Sequence[str]) -> list[str]:
    """The energy columns of a history: the whole-run quantities (names without a dot) other than
    :data:`BOOKKEEPING`."""
    return [c for c in columns if "." not in c and c not in BOOKKEEPING]


def _check_columns(history: Mapping[str, Any], wanted: Sequence[str], where: Path) -> None:
    unknown = [c for c in wanted if c not in history]
    if unknown:
        names = ", ".join(repr(c) for c in unknown)
        raise RunError(f"{where}: no column {names}; its columns are: {', '.join(history)}")


def history_figure(history: Mapping[str, NDArray[np.float64]], columns: Sequence[str], x: str = "time",
                   negate_x: bool = False, negate_y: bool = False, title: str = "",
                   per_metre: bool = False) -> Any:
    """A matplotlib figure with one line per column of ``history`` (column name → values per row)
    against ``x``, each negated when asked; ``per_metre``: forces and energies are per metre of
    thickness (plane strain). Returns the figure (not saved)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.5))
    sign_x, sign_y = (-1.0 if negate_x else 1.0), (-1.0 if negate_y else 1.0)
    abscissa = sign_x * np.asarray(history[x], dtype=float)
    for column in columns:
        ax.plot(abscissa, sign_y * np.asarray(history[column], dtype=float), marker=".", label=_label(column, negate_y, per_metre))
    ax.set_xlabel(_label(x, negate_x, per_metre))
    if len(columns) == 1:
        ax.set_ylabel(_label(columns[0], negate_y, per_metre))
    else:
        ax.legend()
    ax.grid(alpha=0.3)
    if title:
        ax.set_title(title)
    return fig


def _label(column: str, negated: bool, per_metre: bool) -> str:
    """The column's name (with a minus sign when negated) and its SI unit when known."""
    unit = _unit(column, per_metre)
    return ("−" if negated else "") + column + (f" ({unit})" if unit else "")


def _unit(column: str, per_metre: bool) -> str:
    per = "/m" if per_metre else ""
    quantity = column.rsplit(".", 1)[-1]
    if quantity in ("time", "dt", "wall_seconds"):
        return "s"
    if quantity.rsplit("_", 1)[0] in ("force", "base_force", "shaft_force", "applied_force") or quantity == "radial_force_integral":
        return "N" + per
    if quantity.rsplit("_", 1)[0] == "displacement":
        return "m"
    if quantity.endswith(("_energy", "_work", "_dissipation")) or quantity == "energy_residual":
        return "J" + per
    return ""


def plot_history(run_dir: str | Path, columns: Sequence[str] = (), x: str = "time", negate_x: bool = False,
                 negate_y: bool = False, out: str | Path | None = None) -> Path:
    """Draw ``columns`` (default: :func:`energy_columns`) of ``run_dir``'s history.csv against
    ``x`` into ``out`` (default ``RUN/plot.png``); return the PNG's path. ``RunError`` names an
    unknown column and lists the run's columns."""
    run = load_run(run_dir)
    history = run.history
    if not history:
        raise RunError(f"{run.path}: no {HISTORY} rows to plot")
    columns = list(columns) or energy_columns(list(history))
    _check_columns(history, [*columns, x], run.path / HISTORY)
    plane_strain = run.summary.get("formulation") == "plane_strain"  # not the scenario: older runs plot too
    fig = history_figure(history, columns, x=x, negate_x=negate_x, negate_y=negate_y, title=run.path.name,
                         per_metre=plane_strain)
    return save_figure(fig, Path(out) if out is not None else run.path / "plot.png")


def add_parser(sub: Any) -> argparse.ArgumentParser:
    p = sub.add_parser(
        NAME, help="plot history.csv columns of a run against time or another column (PNG)",
        description="Plot columns of a run's history.csv against time (default) or against another "
        "column, as a PNG. Without COLUMN: the energy columns. y points up, so a settlement is a "
        "negative displacement_y: a load-settlement curve is "
        "`axmpm plot RUN BODY.force_y --x BODY.displacement_y --negate-x`.")
    p.add_argument("run_dir", type=Path, metavar="RUN", help="the run's output folder")
    p.add_argument("columns", nargs="*", metavar="COLUMN",
                   help="history.csv columns to plot (default: the energy columns)")
    p.add_argument("--x", default="time", metavar="COLUMN", help="the abscissa column (default: time)")
    p.add_argument("--negate-x", action="store_true", help="plot the negative of the abscissa")
    p.add_argument("--negate-y", action="store_true", help="plot the negative of every COLUMN")
    p.add_argument("--out", type=Path, default=None, metavar="FILE.png", help="the PNG to write (default: RUN/plot.png)")
    return p


def main(args: argparse.Namespace) -> int:
    path = plot_history(args.run_dir, args.columns, x=args.x, negate_x=args.negate_x, negate_y=args.negate_y,
                        out=args.out)
    print(f"wrote {path}")
    return 0
