"""``axmpm resume DIR``: continue an interrupted, killed or failed run from its checkpoint.

The run folder's latest ``checkpoint.npz`` (always at an output time) is restored; frames
and history rows written after it are dropped and the run goes on, appending frames,
history rows and ``particles.pvd`` entries. The final state is bit for bit the one of an
uninterrupted run. Exit codes as ``axmpm run``: 0 completed (or nothing to do), 2 not a
resumable run folder, 3 the simulation failed, 130 interrupted again.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import EXIT_OK
from .output import SUMMARY, read_checkpoint
from .runner import THREADS_HELP, report_run, resume, thread_count

NAME = "resume"


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser(NAME, help="continue an interrupted or killed run from its latest checkpoint")
    p.add_argument("run_dir", type=Path, metavar="DIR", help="the run's output folder")
    p.add_argument("--threads", type=thread_count, default=0, help=THREADS_HELP)
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="show a progress bar (default: when stderr is a terminal)")
    return p


def main(args: argparse.Namespace) -> int:
    if _status(args.run_dir / SUMMARY) == "completed":
        print(f"nothing to resume: {args.run_dir} is a completed run")
        return EXIT_OK
    try:
        start = read_checkpoint(args.run_dir).time
        print(f"resuming {args.run_dir} from its checkpoint at t = {start:.6g} s")
    except (OSError, ValueError):
        pass  # resume() reports the problem
    summary = resume(args.run_dir, threads=args.threads, progress=args.progress)
    return report_run(summary, args.run_dir)


def _status(path: Path) -> str | None:
    import json

    try:
        return json.loads(path.read_text()).get("status")
    except (OSError, ValueError, AttributeError):
        return None
