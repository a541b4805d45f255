"""The tangents Choregraphe's runtime gives a key written without any: BezierAuto.

A key without ``<Tangent>`` elements has BezierAuto tangents
(libqicore-compat ``TangentModel``: ``InterpolationType_BezierAuto`` by
default), which the runtime computes when it loads the timeline
(``TimelinePrivate::rebuildBezierAutoTangents`` and
``updateBezierAutoTangents``) and sends with the keys to
``ALMotion.angleInterpolationBezier``. For a key between two others whose
value lies strictly between theirs, the slope ``beta`` [value per frame] is
the neighbours' (``(right - left) / frames apart``), scaled down so that
neither handle, a third of the way to a neighbour, passes that neighbour's
value (anti-overshoot); at the first and last keys and at a key that is not
between its neighbours (an extremum, or level with one), ``beta`` is 0.
Each handle is a third of the way to the neighbour in time
(``bridge.key_tangents``), so between keys the curve is the cubic Hermite
curve through them with those slopes.

That curve is not the planned one: forced level wherever a joint turns
back and otherwise bent to the neighbours' chords, it bends at every key
(the demo's trajectory at 100 fps asked RElbowYaw for 2.6 times its jerk
limit). armplan's behaviors therefore write their keys' tangents
(``bridge.timeline_keys``); these rules serve to read a file whose keys
have none (``bridge.choregraphe.read_behavior``).
"""

from __future__ import annotations

import numpy as np

from bridge.key_tangents import ALPHA, tangent_handles


def auto_slopes(frames: np.ndarray, values: np.ndarray) -> np.ndarray:
    """BezierAuto slope of every key [value per frame], shape (m, n).

    Args:
        frames: Frame numbers of the keys, increasing, shape (m,).
        values: Their values, shape (m, n) (one column per curve).
    """
    beta = np.zeros_like(values)
    if len(values) < 3:
        return beta
    f = frames.astype(float)[:, None]
    left, x, right = values[:-2], values[1:-1], values[2:]
    between = ((x < right) | (x < left)) & ((x > right) | (x > left))
    slope = (right - left) / (f[2:] - f[:-2])
    slope = _clamped(slope, ALPHA * (f[2:] - f[1:-1]) * slope, right - x)
    slope = _clamped(slope, ALPHA * (f[1:-1] - f[:-2]) * slope, x - left)
    beta[1:-1] = np.where(between, slope, 0.0)
    return beta


def auto_handles(
    frames: np.ndarray, values: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The BezierAuto handles of keys, left and right, each shape (m, n, 2).

    Abscissa [frames] and ordinate [value], offsets from the key, as
    ``bridge.key_tangents.tangent_handles`` gives them for the slopes of
    :func:`auto_slopes`.
    """
    return tangent_handles(frames, auto_slopes(frames, values))


def _clamped(slope: np.ndarray, height: np.ndarray, room: np.ndarray) -> np.ndarray:
    """``slope`` scaled so that a handle of ``height`` rises no more than ``room``."""
    over = np.abs(height) > np.abs(room)
    safe = np.where(over, height, 1.0)
    return np.where(over, slope * room / safe, slope)
