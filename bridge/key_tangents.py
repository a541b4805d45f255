"""The tangents of a Choregraphe timeline's keys: Bezier handles from slopes.

Each ``<Key>`` may hold two ``<Tangent>`` elements, ``side="left"`` and
``side="right"``, ``interpType="bezier"``, whose ``abscissaParam`` and
``ordinateParam`` are the handle's offset from its key: in frames, and in
the curve's unit (degrees, or a hand's open fraction). Choregraphe's
runtime sends each key to ``ALMotion.angleInterpolationBezier`` as
``[value * scale, [type, left abscissa / fps, left ordinate * scale],
[type, right abscissa / fps, right ordinate * scale]]``, ``scale`` being
``TO_RAD`` for a degree curve and 1 for a hand's (libqicore-compat
``timeline.cpp``, ``prepareInterpolationCommand``; ``TangentModel`` reads
the attributes, ``KeyModel`` takes 0 or 2 tangents per key).

With a key's handles a third of the way to its neighbours in time
(``ALPHA``), at heights ``-slope * span / 3`` (left) and ``slope * span /
3`` (right), the Bezier's time runs evenly between two keys and its value
is the cubic Hermite curve through them with those slopes. The first key's
left handle and the last key's right handle, which lead nowhere, are
``(0, 0)``, as the runtime's own (BezierAuto) tangents put them.

A slope is held (:func:`held_slopes`) so that both handles stay in the
joint's range: the curve lies in the hull of its control points, so it
stays in the range as the keys do.
"""

from __future__ import annotations

import numpy as np

#: Where a key's handles lie, as a fraction of the way to its neighbour.
ALPHA = 1.0 / 3.0


def key_spans(numbers: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Frames from each key to the key before it and after it, each shape (m,).

    0 where there is none (before the first key, after the last).

    Args:
        numbers: Frame numbers of the keys, increasing, shape (m,).
    """
    gaps = np.diff(np.asarray(numbers, dtype=float))
    if len(numbers) == 0:
        return gaps, gaps
    return np.concatenate([[0.0], gaps]), np.concatenate([gaps, [0.0]])


def held_slopes(
    numbers: np.ndarray,
    values: np.ndarray,
    slopes: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> np.ndarray:
    """``slopes`` scaled down where a handle would leave ``[lower, upper]``.

    A key outside the range, or on its bound with a slope leading out,
    gets the slope 0.

    Args:
        numbers: Frame numbers of the keys, increasing, shape (m,).
        values: Key values, shape (m, n).
        slopes: Slopes at the keys [value per frame], shape (m, n).
        lower: Lowest value a handle may take, shape (n,).
        upper: Highest value a handle may take, shape (n,).

    Returns:
        The held slopes [value per frame], shape (m, n).
    """
    before, after = key_spans(numbers)
    above = np.maximum(upper - values, 0.0)  # room to rise, shape (m, n)
    below = np.maximum(values - lower, 0.0)
    rising = np.minimum(_steepest(above, after), _steepest(below, before))
    falling = np.minimum(_steepest(below, after), _steepest(above, before))
    return np.clip(slopes, -falling, rising)


def _steepest(room: np.ndarray, span: np.ndarray) -> np.ndarray:
    """Steepest slope whose handle over ``span`` frames rises ``room`` at most."""
    frames = ALPHA * span[:, None]
    return np.where(frames > 0.0, room / np.where(frames > 0.0, frames, 1.0), np.inf)


def tangent_handles(
    numbers: np.ndarray, slopes: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Left and right handles of keys with ``slopes``, each shape (m, n, 2).

    ``[..., 0]`` the abscissa [frames], ``[..., 1]`` the ordinate [value],
    offsets from the key; ``(0, 0)`` where a handle leads to no key.

    Args:
        numbers: Frame numbers of the keys, increasing, shape (m,).
        slopes: Slopes at the keys [value per frame], shape (m, n).
    """
    before, after = key_spans(numbers)
    left_x = np.broadcast_to(-ALPHA * before[:, None], slopes.shape)
    right_x = np.broadcast_to(ALPHA * after[:, None], slopes.shape)
    left = np.stack([left_x, left_x * slopes], axis=-1)
    right = np.stack([right_x, right_x * slopes], axis=-1)
    return left + 0.0, right + 0.0  # no -0.0 written
