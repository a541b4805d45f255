"""The motion model's network tables as arrays, and their probabilities.

The tables of the Bayesian network over the primitive M and the five motion
variables (``services.fit.network``), indexed as

    prior[m]              P(m)               fraction of samples moved by m
    start[m]              P(m at a reach's first sample)
    transition[a, b]      P(m_t = b | m_t-1 = a), consecutive samples of a trial
    shoulder[m, s]        P(S_R = s | m)
    elbow[m, s, p, r]     P(E_P = p, E_R = r | S_R = s, m)
    wrist[m, r, p, w]     P(W_P = p, W_R = w | E_R = r, m)

The model message stores counts; :func:`conditionals` normalises them. Kept
in ``shared/`` beside the model message (``motion_model``), which reads them;
``services.fit.conditionals`` counts them from demonstrations.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

#: How many of each table's leading axes are conditions (the rest sum to 1).
CONDITIONED = {
    "prior": 0,
    "start": 0,
    "transition": 1,
    "shoulder": 1,
    "elbow": 2,
    "wrist": 2,
}


class Conditionals(NamedTuple):
    """The network's tables (see the module docstring for each shape).

    As returned by ``count_tables`` they hold counts; ``conditionals``
    normalises them into probabilities.
    """

    primitives: tuple[str, ...]
    prior: np.ndarray
    start: np.ndarray
    transition: np.ndarray
    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray


def conditionals(counts: Conditionals) -> Conditionals:
    """The probability tables of ``counts`` (each normalised over its last axes)."""
    tables = {
        name: normalised(np.asarray(getattr(counts, name), dtype=float), conditioned)
        for name, conditioned in CONDITIONED.items()
    }
    return Conditionals(counts.primitives, **tables)


def normalised(counts: np.ndarray, conditioned: int) -> np.ndarray:
    """``counts`` over their sums on every axis after the first ``conditioned``."""
    axes = tuple(range(conditioned, counts.ndim))
    return counts / counts.sum(axis=axes, keepdims=True)
