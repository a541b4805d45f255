"""A demonstration file's arms are NAO's: its shoulder and segment lengths.

Demonstrations are retargeted to NAO before they are written
(``retarget``): every sample's shoulder is NAO's (of the trial's arm), its
elbow NAO's upper-arm length from it and its wrist NAO's forearm length
from the elbow; only the segments' directions are the person's. The motion
variables are distances over NAO's arm length, so a file written by a
lab's own converter with human arm lengths, or in millimetres, was fitted
without a word: E_P's rate came out 0.795 (human-size arms) or 0.0019
(millimetres) instead of 5.29, the IK weights could not be fitted, and the
model was written anyway. ``read_demos`` and ``write_demos`` refuse such a
trial with ``nao_size_problem``.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from shared.demos.retarget import ArmSize, nao_arm_size
from shared.demos.rotations import FloatArray
from shared.demos.trial import Trial
from shared.robot.side import Side

#: Largest distance of a sample's shoulder from NAO's, and largest
#: difference of its segments' lengths from NAO's [m]: a converter that
#: rounds positions to 1 mm is off by under 2 mm; a human arm (upper arm
#: about 0.3 m against NAO's 0.106 m) by far more.
NAO_SIZE_TOLERANCE = 0.003


@cache
def _nao(side: Side) -> ArmSize:
    """NAO's shoulder and segment lengths for ``side`` (loaded once)."""
    return nao_arm_size(side)


def nao_size_problem(trial: Trial) -> str:
    """What makes ``trial``'s arm not NAO's, or ``""`` if it is NAO's.

    Checks, at every sample, the upper arm's and the forearm's lengths and
    then the shoulder's position against NAO's (``NAO_SIZE_TOLERANCE``), and
    names the first sample off, the length or position found, NAO's, and
    how many times NAO's the length is (3 for a human arm, 1000 for one in
    millimetres).
    """
    size = _nao(Side.parse(trial.arm))
    for segment, length, nao in (
        ("upper arm", _lengths(trial.elbow - trial.shoulder), size.upper_arm),
        ("forearm", _lengths(trial.wrist - trial.elbow), size.forearm),
    ):
        off = np.abs(length - nao) > NAO_SIZE_TOLERANCE
        k = int(np.argmax(off))
        if off[k]:
            return (
                f"its {segment} is {length[k]:.4g} m long at sample {k}, "
                f"{length[k] / nao:.4g} times NAO's {nao:.4g} m"
                f"{_millimetres(length[k] / nao)}: {_RETARGET}"
            )
    away = _lengths(trial.shoulder - size.shoulder)
    k = int(np.argmax(away > NAO_SIZE_TOLERANCE))
    if away[k] > NAO_SIZE_TOLERANCE:
        return (
            f"its shoulder is at {_point(trial.shoulder[k])} m at sample {k}, "
            f"{away[k]:.4g} m from NAO's {Side.parse(trial.arm).value} shoulder at "
            f"{_point(size.shoulder)} m: {_RETARGET}"
        )
    return ""


_RETARGET = (
    "a demonstration file holds arms retargeted to NAO (NAO's shoulder and segment "
    f"lengths within {NAO_SIZE_TOLERANCE * 1000:g} mm, the person's segment "
    "directions; shared/demos/retarget.py, docs/decision.md)"
)


def _lengths(vectors: FloatArray) -> FloatArray:
    """Euclidean lengths of ``vectors`` [m], shape (n, 3) -> (n,)."""
    return np.asarray(np.linalg.norm(vectors, axis=1), dtype=float)


def _millimetres(ratio: float) -> str:
    """A hint when a length ``ratio`` times NAO's looks like millimetres."""
    return " (millimetres?)" if 500.0 <= ratio <= 2000.0 else ""


def _point(p: FloatArray) -> str:
    """A position as ``(0.000, -0.098, 0.100)``."""
    return "(" + ", ".join(f"{float(v):.4g}" for v in p) + ")"
