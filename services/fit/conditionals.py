"""Learning the network's tables from labelled demonstration states.

Every table is a conditional probability table estimated by counting the
demonstration samples (maximum likelihood) with ``smoothing`` pseudo-counts
added to every cell (additive smoothing, so that a state never seen in the
demonstrations keeps a small probability instead of zero):

    prior[m]              P(m)               fraction of samples moved by m
    start[m]              P(m at a reach's first sample)
    transition[a, b]      P(m_t = b | m_t-1 = a), consecutive samples of a trial
    shoulder[m, s]        P(S_R = s | m)
    elbow[m, s, p, r]     P(E_P = p, E_R = r | S_R = s, m)
    wrist[m, r, p, w]     P(W_P = p, W_R = w | E_R = r, m)

``m`` indexes the primitives the demonstrations show (``primitives``), in
the order of ``shared.primitives.MOTION_PRIMITIVES``. A sample whose W_R is
not observed (state -1: the recording has no wrist orientation) counts
1/bins in each W_R cell of its row. The model file stores the counts
(``count_tables``); ``conditionals`` turns them into probabilities (it and
the ``Conditionals`` tuple live beside the model message, in
``shared.messages.model_tables``).
"""

from __future__ import annotations

import numpy as np

from services.fit.variables import E_P, E_R, S_R, W_P, W_R
from shared.messages.model_tables import (
    CONDITIONED,
    Conditionals,
    conditionals,
    normalised,
)

__all__ = ["CONDITIONED", "Conditionals", "conditionals", "count_tables", "normalised"]


def count_tables(
    states: np.ndarray,
    labels: np.ndarray,
    first: np.ndarray,
    primitives: tuple[str, ...],
    bins: int,
    smoothing: float,
) -> Conditionals:
    """Count the tables from demonstration samples (counts + ``smoothing``).

    Args:
        states: Each sample's variable states, shape (n, 5), ints in [0, bins)
            (W_R may be -1: not observed).
        labels: Each sample's primitive, index into ``primitives``, shape (n,).
        first: True where a reach starts, shape (n,).
        primitives: The primitives the labels index.
        bins: States per variable.
        smoothing: Pseudo-count added to every cell (> 0).
    """
    m = len(primitives)
    prior = np.bincount(labels, minlength=m) + smoothing
    start = np.bincount(labels[first], minlength=m) + smoothing
    transition = np.full((m, m), smoothing)
    later = np.flatnonzero(~first)
    np.add.at(transition, (labels[later - 1], labels[later]), 1.0)
    shoulder = np.full((m, bins), smoothing)
    np.add.at(shoulder, (labels, states[:, S_R]), 1.0)
    elbow = np.full((m, bins, bins, bins), smoothing)
    np.add.at(elbow, (labels, states[:, S_R], states[:, E_P], states[:, E_R]), 1.0)
    wrist = np.full((m, bins, bins, bins), smoothing)
    seen = states[:, W_R] >= 0
    np.add.at(
        wrist,
        (labels[seen], states[seen, E_R], states[seen, W_P], states[seen, W_R]),
        1.0,
    )
    blind = np.zeros((m, bins, bins))
    np.add.at(blind, (labels[~seen], states[~seen, E_R], states[~seen, W_P]), 1.0)
    wrist += blind[..., None] / bins
    return Conditionals(primitives, prior, start, transition, shoulder, elbow, wrist)
