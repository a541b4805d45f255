"""Timing helpers for the benchmarks (never used by tests)."""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from typing import NamedTuple

import numpy as np


class Timing(NamedTuple):
    """Wall-clock times of repeated calls [s].

    Attributes:
        samples: One duration per call [s], shape (n,).
    """

    samples: np.ndarray

    @property
    def mean(self) -> float:
        """Mean duration [s]."""
        return float(self.samples.mean())

    def percentile(self, p: float) -> float:
        """The p-th percentile duration [s]."""
        return float(np.percentile(self.samples, p))


def time_calls(
    calls: list[Callable[[], object]], after: Callable[[], object] | None = None
) -> Timing:
    """Run each call once and time it with ``perf_counter`` [s].

    ``after`` (e.g. a progress bar's advance) runs after each call, untimed.
    """
    samples = np.empty(len(calls))
    for i, call in enumerate(calls):
        start = time.perf_counter()
        call()
        samples[i] = time.perf_counter() - start
        if after is not None:
            after()
    return Timing(samples)


def time_rounds(
    calls: Mapping[str, Callable[[], object]],
    rounds: int,
    after: Callable[[], object] | None = None,
    *,
    warm: bool = True,
) -> dict[str, Timing]:
    """Run every call once per round, in turn, and time each [s].

    With ``warm``, every call runs once untimed first: a cold first call
    (toppra's imports and set-up took 264-399 ms against 5 ms warm) would
    otherwise be a round's sample, and with few rounds the median.
    Interleaved, a change of the machine's load during the run slows every
    call alike, so ratios between them hold. ``after`` runs after each
    call, untimed.
    """
    names = list(calls)
    for name in names if warm else ():  # warm-up, untimed
        calls[name]()
    samples = time_calls([calls[name] for name in names] * rounds, after).samples
    return {name: Timing(samples[k :: len(names)]) for k, name in enumerate(names)}
