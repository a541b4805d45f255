"""The benchmarks' timer: rounds interleave the calls (no timing asserted)."""

from __future__ import annotations

from functools import partial

from armplan.bench.timer import time_rounds


def test_rounds_run_every_call_in_turn_and_keep_their_samples_apart() -> None:
    """A warm-up round, then a, b, c, a, b, c; each name gets one sample per
    timed round; the progress callback runs once per timed call."""
    order: list[str] = []
    after: list[None] = []
    calls = {name: partial(order.append, name) for name in "abc"}
    timings = time_rounds(calls, 2, lambda: after.append(None))
    assert order == ["a", "b", "c"] * 3  # the first round untimed
    assert len(after) == 6
    order.clear()
    time_rounds(calls, 2, warm=False)
    assert order == ["a", "b", "c"] * 2
    assert list(timings) == ["a", "b", "c"]
    assert all(len(t.samples) == 2 and t.mean >= 0.0 for t in timings.values())
