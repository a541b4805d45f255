"""g of one primitive, term by term: the AMI along the network (eq. 5-8).

The slow, explicit counterpart of ``Decider.decide``: it builds the joint
probabilities of the primitive node M with the nodes of the arm chain one at
a time and evaluates each transient term with ``information.tmi`` /
``information.tcmi``,

    shoulder  I(M; S_R)                         TMI  (eq. 5)
    elbow     I(M; E_P, E_R | S_R)              TCMI (eq. 6), parallel form
    wrist     I(M; W_P, W_R | S_R, E_P, E_R)    TCMI, parallel form

accumulated in serial form along the chain (eq. 7). Each term's logarithm
is its own; its weight is the joint probability of the whole moment, P(m,
z), so that the three add up exactly to the TMI of the primitive and the
arm's state, the g of ``decider`` (the chain rule). Used by the tests and by
``armplan decide --json`` to show why a primitive won.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from services.decide.information import tcmi, tmi


class Terms(NamedTuple):
    """The AMI terms of every primitive at one moment [nat], each shape (m,)."""

    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray

    @property
    def g(self) -> np.ndarray:
        """Their sum, the g of each primitive (eq. 7), shape (m,)."""
        return np.asarray(self.shoulder + self.elbow + self.wrist, dtype=float)


def ami_terms(
    prior: np.ndarray,
    shoulder: np.ndarray,
    elbow: np.ndarray,
    wrist: np.ndarray,
) -> Terms:
    """The terms from the network's probabilities at the moment's states.

    Args:
        prior: P(m) (given the primitive before), shape (m,).
        shoulder: P(s_r | m) at the moment's S_R state, shape (m,).
        elbow: P(e_p, e_r | s_r, m) at the moment's states, shape (m,).
        wrist: P(w_p, w_r | e_r, m) at the moment's states (summed over W_R
            when it is not observed), shape (m,).
    """
    p_ms = prior * shoulder
    p_s = p_ms.sum()
    p_mse = p_ms * elbow
    p_se = p_mse.sum()
    p_mz = p_mse * wrist
    p_z = p_mz.sum()
    whole = p_mz
    return Terms(
        whole / p_ms * tmi(p_ms, prior, p_s),
        whole / p_mse * tcmi(p_mse, p_ms, p_se, p_s),
        tcmi(p_mz, p_mse, p_z, p_se),
    )
