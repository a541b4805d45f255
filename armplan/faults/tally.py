"""One scenario's count: faults injected, requests and how each ended, crashes.

A scenario is healthy when nothing was lost, unclear or crashed and its
facts show what docs/faults.md says it must show (:func:`unmet`).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from armplan.faults.outcome import Outcome, Result
from shared.text.counted import counted


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
    def unmet(self) -> list[str]:
        """What the scenario had to show and did not, in words (see :func:`unmet`)."""
        return unmet(self.facts)

    @property
    def healthy(self) -> bool:
        """Nothing lost, unclear or crashed, and every promise of its facts kept."""
        clean = self.lost == 0 and self.unclear == 0 and not self.crashes
        return clean and not self.unmet

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
            "unmet": self.unmet,
        }


def unmet(facts: Mapping[str, Any]) -> list[str]:
    """The promises of docs/faults.md that ``facts`` show broken, in words.

    Each scenario's facts carry what it must show; a fact a scenario does
    not report is not checked:

    - a kill: ``recovered`` (every call after the restart answered, every
      process alive again, ``missing`` empty) and, of the ``down_needing``
      calls sent while the process was down that need it (at least one),
      every one failed naming it (``named``);
    - the recorder: every plan succeeded (``all_planned``), the killed
      file holds (``killed_file``) each of the scenario's plans answered
      ``flush_allowance_s`` or more before the kill (``planned_before``),
      and the new one every plan made after the restart (``new_file`` of
      ``planned_after``);
    - a burst: every one of its ``burst`` plans succeeded (``planned``);
    - bad inputs: each of the ``bad`` ones answered with a typed error (or,
      valid after all, ``accepted``), each followed by a good request
      answered (``good_next``), by the same process (``same_process``).
    """
    broken = _kill_unmet(facts) + _recorder_unmet(facts) + _burst_unmet(facts)
    broken += _bad_input_unmet(facts)
    if facts.get("recovered") is False:
        broken.insert(0, "NOT recovered after the restart")
    if facts.get("missing"):
        broken.append("still not alive: " + ", ".join(facts["missing"]))
    return broken


def _kill_unmet(facts: Mapping[str, Any]) -> list[str]:
    if "down_needing" not in facts:
        return []
    needing, named = facts["down_needing"], facts.get("named", 0)
    if needing < 1:
        return ["no call that needs the killed process was sent while it was down"]
    if named < needing:
        return [f"only {named} of the {needing} calls sent while down named it"]
    return []


def _recorder_unmet(facts: Mapping[str, Any]) -> list[str]:
    broken = []
    if facts.get("all_planned") is False:
        broken.append("not every plan succeeded")
    if "killed_file" in facts:
        kept, before = facts["killed_file"], facts.get("planned_before", 1)
        if kept < before:
            allowance = facts.get("flush_allowance_s", 0.0)
            broken.append(
                f"the killed recorder's file holds {kept} of the scenario's "
                f"trajectories, not the {before} planned {allowance:g} s or more "
                "before the kill"
            )
    if "new_file" in facts:
        after = max(facts.get("planned_after", 1), 1)
        if facts["new_file"] < after:
            broken.append(
                "the new recorder's file holds "
                f"{counted(facts['new_file'], 'trajectory', 'trajectories')}, "
                f"not the {after} planned after the restart"
            )
    return broken


def _burst_unmet(facts: Mapping[str, Any]) -> list[str]:
    if "burst" not in facts:
        return []
    burst, planned = facts["burst"], facts.get("planned", 0)
    if planned < burst:
        return [f"only {planned} of the {burst} plans sent at once succeeded"]
    return []


def _bad_input_unmet(facts: Mapping[str, Any]) -> list[str]:
    if "bad" not in facts:
        return []
    bad = facts["bad"]
    answered = facts.get("typed", 0) + facts.get("accepted", 0)
    broken = []
    if answered < bad:
        broken.append(f"{bad - answered} of {bad} bad inputs got no typed error")
    if facts.get("good_next", 0) < bad:
        broken.append(
            f"the good request right after one answered {facts.get('good_next', 0)} "
            f"of {bad} times"
        )
    if facts.get("same_process") is False:
        broken.append("not the same process at the end")
    return broken
