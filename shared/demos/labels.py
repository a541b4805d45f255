"""Which motion primitive moves the arm, from which of its joints move.

Used by the synthetic generator (it knows which joints it moves) and by the
labelling of recorded data (``services.fit.labelling`` measures it). A
moving shoulder turns (S_R) and carries the elbow (E_P); a flexing elbow
turns (E_R); a rolling forearm turns the wrist (W_R); the wrist moves (W_P)
whenever shoulder or elbow does.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: Label of a reach's first samples when nothing moves yet.
FIRST = "S_R E_P W_P"


def primitive_name(shoulder: bool, elbow: bool, roll: bool) -> str | None:
    """The motion primitive of a set of moving joints; ``None`` if none applies.

    The forearm's roll counts only while shoulder and elbow move together:
    the S_R E_PR W_PR phase. Alone or with one joint it is ignored (the
    wrist-turning primitives of one joint are not modelled from reaches).
    """
    if not (shoulder or elbow):
        return None
    roll = roll and shoulder and elbow
    terms = ["S_R"] if shoulder else []
    elbow_attr = ("P" if shoulder else "") + ("R" if elbow else "")
    terms.append(f"E_{elbow_attr}")
    terms.append("W_PR" if roll else "W_P")
    return " ".join(terms)


def labels_from_motion(
    shoulder: npt.NDArray[np.bool_],
    elbow: npt.NDArray[np.bool_],
    roll: npt.NDArray[np.bool_],
) -> list[str]:
    """Per sample the primitive whose joints move, shape (n,).

    Samples where nothing moves take the label of the last moving sample
    before them (at the start, of the first one after).

    Args:
        shoulder: Whether the shoulder moves at each sample, shape (n,).
        elbow: Whether the elbow flexes, shape (n,).
        roll: Whether the forearm rolls, shape (n,).
    """
    names = [
        primitive_name(bool(s), bool(e), bool(r))
        for s, e, r in zip(shoulder, elbow, roll, strict=True)
    ]
    first = next((name for name in names if name is not None), FIRST)
    out, last = [], first
    for name in names:
        last = name or last
        out.append(last)
    return out
