"""The compiled engine, ``axmpm._core`` (Rust, PyO3 bindings), loaded on first use: ``import
axmpm`` needs neither the build nor the engine's start-up. Every module reaches the engine
through :func:`core`, which says how to build it when it is missing."""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["core"]


def core() -> ModuleType:
    """The module ``axmpm._core``; ``ImportError`` naming ``make install`` when it is not built."""
    try:
        return importlib.import_module("axmpm._core")
    except ImportError as exc:  # pragma: no cover - depends on the build
        raise ImportError(f"the compiled engine axmpm._core is not available ({exc}); run `make install`") from None
