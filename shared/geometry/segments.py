"""Closest distance between line segments, many pairs at once.

A capsule (a segment swept by a ball) and a ball (a segment of length 0)
are what the body check (``shared.robot.body``) is made of: two of them
overlap when the distance between their segments is less than the sum of
their radii. The closest points are found as in Ericson's *Real-Time
Collision Detection* (section 5.1.9): the closest points of the two lines,
each parameter clamped to its segment, the other parameter then found
again for the clamped one and clamped in turn.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: Squared length under which a segment is a point [m^2].
POINT = 1e-18


def segment_distance(
    p0: npt.ArrayLike, p1: npt.ArrayLike, q0: npt.ArrayLike, q1: npt.ArrayLike
) -> np.ndarray:
    """Closest distance [m] between segments ``p0 p1`` and ``q0 q1``.

    Args:
        p0: One end of the first segments [m], shape (..., 3).
        p1: Their other end [m], shape (..., 3).
        q0: One end of the second segments [m], shape (..., 3).
        q1: Their other end [m], shape (..., 3); the four broadcast together.

    Returns:
        The distances [m], the broadcast shape without its last axis. A
        segment whose ends coincide is a point.
    """
    p0, p1, q0, q1 = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (p0, p1, q0, q1))
    )
    s, t = _closest_parameters(p1 - p0, q1 - q0, p0 - q0)
    nearest_p = p0 + s[..., None] * (p1 - p0)
    nearest_q = q0 + t[..., None] * (q1 - q0)
    return np.linalg.norm(nearest_p - nearest_q, axis=-1)


def _closest_parameters(
    d1: np.ndarray, d2: np.ndarray, r: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Parameters s, t in [0, 1] of the closest points of p0 + s d1 and q0 + t d2.

    ``r`` is p0 - q0; all shape (..., 3).
    """
    a = np.einsum("...i,...i", d1, d1)
    e = np.einsum("...i,...i", d2, d2)
    b = np.einsum("...i,...i", d1, d2)
    c = np.einsum("...i,...i", d1, r)
    f = np.einsum("...i,...i", d2, r)
    p_line, q_line = a > POINT, e > POINT
    denominator = a * e - b * b
    crossing = p_line & q_line & (denominator > POINT * (a + e))
    s = np.where(crossing, _clamp(_divide(b * f - c * e, denominator)), 0.0)
    t = np.where(q_line, _divide(b * s + f, e), 0.0)
    below, above = t < 0.0, t > 1.0
    t = _clamp(t)
    # t clamped: s found again for that end of the second segment
    again = np.where(above, _divide(b - c, a), _divide(-c, a))
    s = np.where(p_line & (below | above), _clamp(again), s)
    s = np.where(p_line & ~q_line, _clamp(_divide(-c, a)), s)
    return np.where(p_line, s, 0.0), t


def _divide(numerator: np.ndarray, denominator: np.ndarray) -> np.ndarray:
    """numerator / denominator, 0 where the denominator is 0."""
    safe = np.where(denominator == 0.0, 1.0, denominator)
    return np.where(denominator == 0.0, 0.0, numerator / safe)


def _clamp(value: np.ndarray) -> np.ndarray:
    return np.clip(value, 0.0, 1.0)
