"""Cores, process pools and Dask clients: the one place that decides how many runs go in
parallel. dask and distributed are imported only when a client is opened (they take about a
second to import)."""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any

from ..errors import RunError

__all__ = ["available_cores", "process_pool", "default_workers", "open_client"]


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
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(method))


def default_workers(threads_per_run: int = 1) -> int:
    """Runs that fit at once: the available cores over the threads of one run (at least 1)."""
    return max(1, available_cores() // max(1, threads_per_run))


@contextmanager
def open_client(
    scheduler: str | None = None,
    workers: int | None = None,
    threads_per_run: int = 1,
    processes: bool = True,
) -> Iterator[Any]:
    """A ``distributed.Client``: to ``scheduler`` when given, else to a fresh LocalCluster
    of ``workers`` single-threaded workers (processes by default: a process isolates a run that crashes or leaks memory)."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise RunError(f"cannot connect to the Dask scheduler at {scheduler}: {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = workers if workers and workers > 0 else default_workers(threads_per_run)
    # A run that kills its worker (engine crash) is retried once, then recorded as failed.
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=processes,
            dashboard_address=None,
            silence_logs=logging.ERROR,
        )
        try:
            client = Client(cluster)
            try:
                yield client
            finally:
                client.close()
        finally:
            cluster.close()
