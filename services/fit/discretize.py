"""States of the motion variables: equal-probability bins of their densities.

The network's variables are discrete. Each motion variable's fitted
exponential density (``exponential``) cuts its range into ``bins`` states of
equal probability 1/bins: the edges are the density's quantiles k/bins. The
bins are narrow near 0, where a movement's last part lives, and wide in the
tail.
"""

from __future__ import annotations

import bisect

import numpy as np

from services.fit.exponential import quantiles


def bin_edges(rate: float, bins: int) -> np.ndarray:
    """Inner edges of ``bins`` equal-probability bins, shape (bins - 1,)."""
    return quantiles(rate, np.arange(1, bins) / bins)


def bin_indices(x: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """State (0 .. len(edges)) of each value of ``x``, shape of ``x``.

    A value on an edge belongs to the bin above it.
    """
    return np.searchsorted(edges, x, side="right")


def bin_index(value: float, edges: list[float]) -> int:
    """State of one value (the fast path of :func:`bin_indices`)."""
    return bisect.bisect_right(edges, value)
