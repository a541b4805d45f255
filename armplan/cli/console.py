"""A rich console for stdout that leaves a closed pipe to ``main``.

rich's ``Console`` turns a ``BrokenPipeError`` (``armplan inspect f.mcap |
head -2``: the reader left) into ``SystemExit(1)``; :func:`armplan.cli.main.main`
already ends such a run quietly with exit 0, as other command-line tools do,
so this console hands it the error instead.
"""

from __future__ import annotations

from rich.console import Console


class StdoutConsole(Console):
    """``rich.console.Console`` that raises ``BrokenPipeError`` on a closed pipe."""

    def on_broken_pipe(self) -> None:
        """Stop writing and let ``main`` end the run (exit 0)."""
        self.quiet = True
        raise BrokenPipeError


__all__ = ["StdoutConsole"]
