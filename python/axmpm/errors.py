"""Error types shared by the front end.

Input errors (bad scenario, bad output folder) carry the dotted key of every problem so
that the CLI can print one line per error and exit with status 2, without a traceback.
"""

from __future__ import annotations

from collections.abc import Iterable

#: Exit codes of the ``axmpm`` command (see :mod:`axmpm.cli`).
EXIT_OK = 0
EXIT_FAILED_CHECK = 1  # a verification or validation check failed
EXIT_INPUT = 2  # bad input: one ``error: key: message`` line per problem, no traceback
EXIT_FAILED = 3  # the run failed (the engine's reason, or writing its output)
EXIT_INTERRUPTED = 130  # Ctrl-C


class ScenarioError(Exception):
    """One or more problems in a scenario, each as ``(dotted key, message)``.

    ``str(error)`` renders one line per problem::

        error: materials.sand.poisson_ratio: must be >= 0 and < 0.5 (got 0.7)

    An empty key means the problem concerns the whole file (e.g. a TOML syntax error).
    Deliberately not a ``ValueError``, so that pydantic validators can raise it unchanged.
    """

    def __init__(self, errors: Iterable[tuple[str, str]] | str, source: str | None = None):
        if isinstance(errors, str):
            errors = [("", errors)]
        self.errors: list[tuple[str, str]] = [(str(k), str(m)) for k, m in errors]
        self.source = source
        super().__init__(self.render())

    def render(self) -> str:
        """One line per problem; control characters in keys or messages (a key may be any
        string in TOML) are escaped, so that each problem stays on one line."""
        lines = []
        for key, message in self.errors:
            key, message = _one_line(key), _one_line(message)
            lines.append(f"error: {key}: {message}" if key else f"error: {message}")
        return "\n".join(lines)

    def __str__(self) -> str:  # pragma: no cover - trivial
        return self.render()

    @property
    def keys(self) -> list[str]:
        return [k for k, _ in self.errors]


class RunError(Exception):
    """A run could not start or resume (bad output folder, engine missing or rejecting the
    scenario, a run folder without a usable checkpoint)."""

    def render(self) -> str:
        return f"error: {_one_line(str(self))}"


def _one_line(text: str) -> str:
    """``text`` with every non-printable character (newline, tab, control) escaped."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)
