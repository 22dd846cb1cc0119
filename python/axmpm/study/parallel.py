"""Cores and process pools: the one place that decides how many runs go in parallel."""

from __future__ import annotations

import os
from typing import Any

__all__ = ["available_cores", "process_pool"]


def available_cores() -> int:
    """Cores available to this process (its CPU affinity, not the machine's count)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - non-Linux
        return os.cpu_count() or 1


def process_pool(workers: int) -> Any:
    """A ``ProcessPoolExecutor`` of ``workers`` processes started by fork where available: no
    engine or thread pool exists in the parent yet, and unlike spawn fork does not re-import the
    caller's main module (scripts without a ``__main__`` guard work)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(method))
