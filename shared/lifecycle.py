"""Things that start and stop, and serve as context managers.

``with Launcher(...) as launcher:`` starts on entry and stops on exit,
whatever the exit: a subclass writes ``start`` (returning itself, ready)
and ``stop`` (callable with no arguments), and inherits the ``with``.
"""

from __future__ import annotations

from types import TracebackType
from typing import Any, Self


class StartStop:
    """Base of a process, stack or service that starts and stops."""

    def start(self) -> Any:
        """Start; return ``self`` once ready."""
        raise NotImplementedError

    def stop(self) -> Any:
        """Stop and release everything ``start`` took."""
        raise NotImplementedError

    def __enter__(self) -> Self:
        self.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.stop()
