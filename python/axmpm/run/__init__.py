"""Running a scenario and its run folder.

* :mod:`.runner`: the engine loop (output times, stop tests, checkpoints, failures);
* :mod:`.output`: what a run folder holds and how it is read back (:func:`load_run`);
* :mod:`.lock`: one writer per run folder;
* :mod:`.resume`: ``axmpm resume DIR``.

``axmpm.run(scenario, out, ...)`` keeps working: this package is callable and calls
:func:`axmpm.run.runner.run` (``axmpm.run.run`` is the same function).
"""

from __future__ import annotations

import sys
import types
from typing import Any

from .output import Run, load_run
from .runner import resume, run

__all__ = ["run", "resume", "load_run", "Run"]


class _CallablePackage(types.ModuleType):
    """``axmpm.run`` is both this package and the function :func:`~axmpm.run.runner.run`."""

    def __call__(self, *args: Any, **kwargs: Any) -> dict[str, Any]:
        return run(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
