"""Corners of a joint path, where the arm stops instead of rounding them.

Where consecutive steps of the path turn sharply in (speed-scaled) joint
space, e.g. a joint stopping dead against its limit while the others go on,
or a change of primitive, no timing can follow the path at speed: the
direction of motion jumps, so the acceleration would be unbounded unless the
speed is nearly zero there. The timing therefore stops at such a corner: the
path is split there, and each side is timed from rest to rest by its own
spline (which then does not have to bend round the corner at all, so the
corner is followed exactly). Gentler turns stay inside one spline, which
rounds them; the stretch that keeps every limit then allows for them.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np

#: Turn between consecutive steps, in speed-scaled joint space, that makes a
#: corner [rad] (smooth paths sampled at 100 Hz turn by less than 0.2 rad).
CORNER_ANGLE = 0.3
#: Shortest section a corner may cut off, as a share of the path's length:
#: near the ends the arm is slow anyway, and the stretch that keeps every
#: limit (:func:`services.timing.time_path.required_stretch`) handles a turn
#: there.
SHORTEST_SECTION = 0.05


def corner_indices(
    points: np.ndarray, velocity: np.ndarray, angle: float = CORNER_ANGLE
) -> np.ndarray:
    """Indices of inner points (K, n) where the path turns by more than ``angle``.

    Corners closer than ``SHORTEST_SECTION`` of the path's length to an end
    or to the previous corner are left out.

    Args:
        points: Path points without repeats [rad], shape (K, n).
        velocity: Speed limits [rad/s], shape (n,): the joints' scale.
        angle: Smallest turn that is a corner [rad].

    Returns:
        Increasing indices in 1..K-2, shape (c,).
    """
    steps = np.diff(points, axis=0) / velocity
    length = np.linalg.norm(steps, axis=1)
    cosine = np.einsum("ij,ij->i", steps[:-1], steps[1:]) / (length[:-1] * length[1:])
    candidates = np.flatnonzero(cosine < np.cos(angle)) + 1
    along = np.concatenate(([0.0], np.cumsum(length)))
    along /= along[-1]
    kept: list[int] = []
    for k in candidates:
        last = along[kept[-1]] if kept else 0.0
        if along[k] - last >= SHORTEST_SECTION and 1.0 - along[k] >= SHORTEST_SECTION:
            kept.append(int(k))
    return np.array(kept, dtype=int)


def sections(count: int, corners: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) point index of each section between corners, inclusive."""
    bounds = [0, *(int(c) for c in corners), count - 1]
    return list(pairwise(bounds))


__all__ = ["CORNER_ANGLE", "SHORTEST_SECTION", "corner_indices", "sections"]
