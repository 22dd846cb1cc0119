"""Small matplotlib helpers shared by the front end's reports.

matplotlib is imported lazily (``import axmpm`` must not need it) and always with the
non-interactive Agg backend, so figures can be written on a machine without a display.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["pyplot", "save_figure", "SCHEME_STYLES", "scheme_style"]

#: One colour and marker per interpolation scheme, the same in every figure.
SCHEME_STYLES: dict[str, dict[str, Any]] = {
    "linear": {"color": "tab:red", "marker": "o", "label": "original MPM"},
    "ugimp": {"color": "tab:orange", "marker": "s", "label": "uGIMP"},
    "cpgimp": {"color": "tab:green", "marker": "^", "label": "cpGIMP"},
    "cpdi2": {"color": "tab:blue", "marker": "D", "label": "CPDI2"},
}


def scheme_style(scheme: str) -> dict[str, Any]:
    """Colour, marker and legend label of a scheme (grey circle for an unknown one)."""
    return dict(SCHEME_STYLES.get(scheme, {"color": "tab:gray", "marker": "o", "label": scheme}))


def pyplot() -> Any:
    """``matplotlib.pyplot`` with the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig: Any, path: str | Path, dpi: int = 120) -> Path:
    """Save a figure as PNG (creating the folder), close it, return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    pyplot().close(fig)
    return path
