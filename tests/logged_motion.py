"""The motion the simulated NAO logged: each joint's peak speed, acceleration, jerk."""

from __future__ import annotations

from typing import Any

import numpy as np


def divided(t: np.ndarray, q: np.ndarray, order: int) -> np.ndarray:
    """``order!`` times the ``order``-th divided differences of ``q`` at ``t``."""
    d = q.copy()
    for k in range(1, order + 1):
        d = k * np.diff(d) / (t[k:] - t[:-k])
    return d


def logged_peaks(
    entries: list[dict[str, Any]], names: list[str], since: float, until: float
) -> np.ndarray:
    """Peak |speed|, |acceleration|, |jerk| of ``names`` [rad/s^k], shape (3, n).

    From the measured positions of the ``state`` lines logged at ``since``
    <= t <= ``until`` [s, the log's clock] (a joint not logged: 0).
    """
    peaks = np.zeros((3, len(names)))
    for j, name in enumerate(names):
        rows = [
            (e["t"], e["positions"][name])
            for e in entries
            if e["event"] == "state"
            and since <= e["t"] <= until
            and name in e["positions"]
        ]
        if len(rows) < 4:
            continue
        t, q = np.array(rows).T
        for order in (1, 2, 3):
            peaks[order - 1, j] = np.abs(divided(t, q, order)).max()
    return peaks
