"""One scenario's count: faults injected, requests and how each ended, crashes."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from armplan.faults.outcome import Outcome, Result


@dataclass
class Tally:
    """What one scenario did and saw.

    Attributes:
        scenario: Its name, e.g. ``"kill decide"``.
        faults: Faults injected (kills, restarts count once per kill).
        results: How each request ended, in the order sent.
        crashes: Processes that exited without being killed, ``name (pid)``.
        facts: What showed the fault happened and healed, e.g.
            ``{"down": 20, "recovered": True}``.
    """

    scenario: str
    faults: int = 0
    results: list[Result] = field(default_factory=list)
    crashes: list[str] = field(default_factory=list)
    facts: dict[str, Any] = field(default_factory=dict)

    def add(self, results: Iterable[Result]) -> list[Result]:
        """Keep ``results``; returns them as a list."""
        kept = list(results)
        self.results += kept
        return kept

    def count(self, outcome: Outcome) -> int:
        """Requests that ended with ``outcome``."""
        return sum(1 for r in self.results if r.outcome is outcome)

    @property
    def sent(self) -> int:
        """Requests sent."""
        return len(self.results)

    @property
    def lost(self) -> int:
        """Requests without an answer in time, or with an untyped failure."""
        return self.count(Outcome.LOST)

    @property
    def unclear(self) -> int:
        """Requests answered with ``internal_error`` or ``remote_error``."""
        return self.count(Outcome.UNCLEAR)

    @property
    def healthy(self) -> bool:
        """Nothing lost, unclear or crashed, and recovered after a restart."""
        recovered = self.facts.get("recovered", True) is not False
        clean = self.lost == 0 and self.unclear == 0 and not self.crashes
        return clean and recovered

    def kinds(self) -> dict[str, int]:
        """How many requests ended with each error kind (not successes)."""
        return dict(Counter(r.kind for r in self.results if r.kind))

    def row(self) -> dict[str, Any]:
        """The table's row: the counts, the error kinds and the facts."""
        return {
            "scenario": self.scenario,
            "faults": self.faults,
            "sent": self.sent,
            "succeeded": self.count(Outcome.SUCCEEDED),
            "typed": self.count(Outcome.TYPED),
            "unclear": self.unclear,
            "lost": self.lost,
            "crashes": len(self.crashes),
            "kinds": self.kinds(),
            "crashed": list(self.crashes),
            "facts": dict(self.facts),
        }
