"""The benchmarks' timer: rounds interleave the calls (no timing asserted)."""

from __future__ import annotations

from functools import partial

from armplan.bench.timer import time_rounds


def test_rounds_run_every_call_in_turn_and_keep_their_samples_apart() -> None:
    """Order a, b, c, a, b, c; each name gets one sample per round; the
    progress callback runs once per call."""
    order: list[str] = []
    after: list[None] = []
    calls = {name: partial(order.append, name) for name in "abc"}
    timings = time_rounds(calls, 2, lambda: after.append(None))
    assert order == ["a", "b", "c", "a", "b", "c"]
    assert len(after) == 6
    assert list(timings) == ["a", "b", "c"]
    assert all(len(t.samples) == 2 and t.mean >= 0.0 for t in timings.values())
