"""Transient mutual information and its accumulation (paper eq. 5-8).

The pointwise ("transient") terms of mutual information at one moment:

    TMI   I(X, Y)     = P(x, y) log[ P(x, y) / (P(x) P(y)) ]            (5)
    TCMI  I(X, Z | Y) = P(x, y, z) log[ P(y) P(x, y, z) / (P(x, y) P(y, z)) ]  (6)

Summed over every state (x, y) they give the mutual information I(X; Y);
over every (x, y, z) the conditional mutual information I(X; Z | Y). Eq. 6
as printed lacks the factor P(y) inside the logarithm; without it the sum
is not a conditional mutual information (it adds H(Y)), so it is kept here.

The accumulated mutual information (AMI) adds such terms along the network:
the serial form (eq. 7) along a chain of nodes, the parallel form (eq. 8)
over variables that share a parent. Functions take probabilities as floats
or numpy arrays (elementwise); a zero joint probability gives a zero term.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np


def tmi(p_xy: np.ndarray, p_x: np.ndarray, p_y: np.ndarray) -> np.ndarray:
    """Transient mutual information (eq. 5) [nat], shape of the inputs."""
    p_xy = np.asarray(p_xy, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = p_xy * np.log(p_xy / (np.asarray(p_x) * np.asarray(p_y)))
    return np.where(p_xy > 0, terms, 0.0)


def tcmi(
    p_xyz: np.ndarray, p_xy: np.ndarray, p_yz: np.ndarray, p_y: np.ndarray
) -> np.ndarray:
    """Transient conditional mutual information of X and Z given Y (eq. 6) [nat]."""
    p_xyz = np.asarray(p_xyz, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.asarray(p_y) * p_xyz / (np.asarray(p_xy) * np.asarray(p_yz))
        terms = p_xyz * np.log(ratio)
    return np.where(p_xyz > 0, terms, 0.0)


def ami_serial(terms: Iterable[float]) -> float:
    """AMI in serial form (eq. 7): the sum of the TMIs along a chain [nat]."""
    return float(sum(terms))


def ami_parallel(terms: Iterable[float]) -> float:
    """AMI in parallel form (eq. 8): the sum of the TCMIs of sibling variables."""
    return float(sum(terms))
