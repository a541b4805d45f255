"""The primitive matrix e and MP_form = a e j (paper, equation 2).

``a = [P, R, PR]`` is the attribute vector (rows of e) and ``j = [S, E, W]``
the joint vector (columns of e). Each 1 at row i, column k contributes the
term "joint k with attribute i", so the product a e j spells the primitive's
name, e.g. e = [[0,1,1],[1,0,0],[0,0,0]] gives ``"S_R E_P W_P"``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from shared.errors import InvalidInputError

#: Attribute vector a (rows of e): position change, orientation change, both.
ATTRIBUTES: tuple[str, ...] = ("P", "R", "PR")
#: Joint vector j (columns of e): shoulder, elbow, wrist.
NODES: tuple[str, ...] = ("S", "E", "W")

PrimitiveMatrix = tuple[
    tuple[int, int, int], tuple[int, int, int], tuple[int, int, int]
]


def check_matrix(e: Sequence[Sequence[int]]) -> np.ndarray:
    """Validate a primitive matrix: 3x3, entries 0/1, at most one 1 per column.

    Returns:
        The matrix as an int array, shape (3, 3).
    """
    m = np.asarray(e)
    if m.shape != (3, 3) or not np.isin(m, (0, 1)).all():
        raise InvalidInputError(
            f"a primitive matrix is 3x3 with entries 0 or 1, got {m.tolist()}",
            field="e",
        )
    if (m.sum(axis=0) > 1).any():
        raise InvalidInputError(
            f"a joint has two attributes in primitive matrix {m.tolist()}", field="e"
        )
    if m.sum() == 0:
        raise InvalidInputError("a primitive matrix needs at least one 1", field="e")
    return m.astype(int)


def mp_form_terms(e: Sequence[Sequence[int]]) -> tuple[tuple[str, str], ...]:
    """The terms of a e j as (node, attribute) pairs in joint order S, E, W."""
    m = check_matrix(e)
    terms = []
    for col, node in enumerate(NODES):
        rows = np.flatnonzero(m[:, col])
        if rows.size:
            terms.append((node, ATTRIBUTES[int(rows[0])]))
    return tuple(terms)


def mp_form(e: Sequence[Sequence[int]]) -> str:
    """The primitive's name a e j, e.g. ``"S_R E_PR W_P"`` (equation 2)."""
    return " ".join(f"{node}_{attr}" for node, attr in mp_form_terms(e))


def matrix_from_mp_form(name: str) -> PrimitiveMatrix:
    """The primitive matrix e whose product a e j is ``name`` (inverse of mp_form)."""
    m = [[0, 0, 0], [0, 0, 0], [0, 0, 0]]
    for term in name.split():
        node, _, attr = term.partition("_")
        if node not in NODES or attr not in ATTRIBUTES:
            raise InvalidInputError(
                f"{term!r} is not a term like 'S_R' or 'E_PR'", field="name"
            )
        col = NODES.index(node)
        if any(m[row][col] for row in range(3)):
            raise InvalidInputError(f"{node} appears twice in {name!r}", field="name")
        m[ATTRIBUTES.index(attr)][col] = 1
    result = tuple(tuple(row) for row in m)
    check_matrix(result)
    return result  # type: ignore[return-value]
