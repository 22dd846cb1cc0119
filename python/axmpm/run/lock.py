"""One writer per run folder: ``run.lock``.

A process that writes a run folder (``axmpm run``, ``axmpm resume``, and the runs of ``verify``,
``validate``, ``sweep``) holds an exclusive ``flock`` on ``DIR/run.lock``, whose content names the
holder (pid, host, command, start time). A second writer finds the lock taken and refuses,
naming the holder (:class:`~axmpm.errors.RunError`, exit 2). The kernel releases the lock when
the holder exits, however it exits; the file is removed on a normal release. A lock file left
by a dead process (killed, crashed, the machine rebooted) is not locked any more and is taken
over. Without ``fcntl`` (not POSIX), the file is created exclusively instead and a lock file of
a dead process on the same host is taken over.
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from ..errors import RunError

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None  # type: ignore[assignment]

__all__ = ["LOCK", "RunLock", "locked", "holder_of"]

LOCK = "run.lock"


def _describe(holder: dict[str, Any] | None) -> str:
    if not holder:
        return "another process (the lock file names no holder)"
    since = holder.get("since")
    when = f", since {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(since))}" if since else ""
    command = f" ({holder['command']})" if holder.get("command") else ""
    return f"pid {holder.get('pid')} on {holder.get('host')}{command}{when}"


def holder_of(folder: str | Path) -> dict[str, Any] | None:
    """The holder recorded in ``folder/run.lock`` (None when absent or unreadable)."""
    try:
        data = json.loads((Path(folder) / LOCK).read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


class RunLock:
    """The lock of one run folder; :meth:`acquire` raises :class:`RunError` naming the holder."""

    def __init__(self, folder: str | Path, command: str | None = None):
        self.folder = Path(folder)
        self.path = self.folder / LOCK
        self.command = command if command is not None else " ".join(["axmpm", *sys.argv[1:2]])
        self._fd: int | None = None

    @property
    def held(self) -> bool:
        return self._fd is not None

    def _content(self) -> bytes:
        return (json.dumps({"pid": os.getpid(), "host": socket.gethostname(), "command": self.command,
                            "since": time.time()}) + "\n").encode()

    def _refuse(self, holder: dict[str, Any] | None) -> RunError:
        return RunError(f"{self.folder} is being written by {_describe(holder)}; wait for it to finish "
                        f"or stop it (a lock of a process that no longer runs is taken over: {self.path})")

    def acquire(self) -> "RunLock":
        if self._fd is not None:
            return self
        self.folder.mkdir(parents=True, exist_ok=True)
        if fcntl is None:  # pragma: no cover - not POSIX
            return self._acquire_exclusive()
        for _ in range(10):
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                raise self._refuse(holder_of(self.folder)) from None
            try:  # the file we locked must still be the one at the path (not removed meanwhile)
                same = os.path.samestat(os.fstat(fd), os.stat(self.path))
            except FileNotFoundError:
                same = False
            if not same:
                os.close(fd)
                continue
            os.ftruncate(fd, 0)
            os.write(fd, self._content())
            self._fd = fd
            return self
        raise self._refuse(holder_of(self.folder))  # pragma: no cover - a lock file that keeps changing

    def _acquire_exclusive(self) -> "RunLock":  # pragma: no cover - not POSIX
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                holder = holder_of(self.folder)
                stale = (holder is not None and holder.get("host") == socket.gethostname()
                         and isinstance(holder.get("pid"), int) and not _alive(holder["pid"]))
                if not stale:
                    raise self._refuse(holder) from None
                with contextlib.suppress(FileNotFoundError):
                    self.path.unlink()
                continue
            os.write(fd, self._content())
            self._fd = fd
            return self
        raise self._refuse(holder_of(self.folder))

    def release(self) -> None:
        """Remove the lock file and unlock (nothing if not held)."""
        if self._fd is None:
            return
        fd, self._fd = self._fd, None
        with contextlib.suppress(OSError):
            if os.path.samestat(os.fstat(fd), os.stat(self.path)):
                self.path.unlink()
        os.close(fd)  # closing the descriptor releases the flock

    def __enter__(self) -> "RunLock":
        return self.acquire()

    def __exit__(self, *exc: Any) -> None:
        self.release()


@contextlib.contextmanager
def locked(folder: str | Path, command: str | None = None) -> Iterator[RunLock]:
    """Hold the lock of ``folder`` (created if missing) for the ``with`` block."""
    lock = RunLock(folder, command).acquire()
    try:
        yield lock
    finally:
        lock.release()
