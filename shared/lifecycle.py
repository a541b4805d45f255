"""Things that start and stop, or close, and serve as context managers.

``with Launcher(...) as launcher:`` starts on entry and stops on exit,
whatever the exit: a subclass of :class:`StartStop` writes ``start``
(returning once ready) and ``stop`` (callable with no arguments), and
inherits the ``with``. A subclass of :class:`Closes` is ready once built and
writes ``close``.
"""

from __future__ import annotations

from types import TracebackType
from typing import Any, Self


class Closes:
    """Base of a session, writer or pool that is ready once built and closes."""

    def close(self) -> Any:
        """Release everything held."""
        raise NotImplementedError

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close()


class StartStop(Closes):
    """Base of a process, stack or service that starts and stops.

    Entering starts it; closing (as on leaving the ``with``) stops it.
    """

    def start(self) -> Any:
        """Start; return once ready."""
        raise NotImplementedError

    def stop(self) -> Any:
        """Stop and release everything ``start`` took."""
        raise NotImplementedError

    def close(self) -> None:
        """Stop (what leaving the ``with`` does)."""
        self.stop()

    def __enter__(self) -> Self:
        self.start()
        return self
