"""Rotations for the demonstration code: axis-angle, frame interpolation, quaternions.

Conversions are named ``<to>_from_<from>``. Quaternions are (w, x, y, z),
unit, with w >= 0. Everything works on stacks: a leading axis of length n.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

_EPS = 1e-12


def skew(v: FloatArray) -> FloatArray:
    """Cross-product matrices [v]x of vectors, shape (..., 3) -> (..., 3, 3)."""
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    k = np.zeros((*np.shape(x), 3, 3), dtype=np.result_type(v, 0.0))
    k[..., 0, 1], k[..., 0, 2] = -z, y
    k[..., 1, 0], k[..., 1, 2] = z, -x
    k[..., 2, 0], k[..., 2, 1] = -y, x
    return k


def matrix_from_rotation_vector(rv: FloatArray) -> FloatArray:
    """Rotation matrices from rotation vectors (axis times angle [rad]) (Rodrigues).

    Args:
        rv: Rotation vectors, shape (..., 3).

    Returns:
        Rotation matrices, shape (..., 3, 3).
    """
    angle = np.linalg.norm(rv, axis=-1)[..., None, None]
    k = skew(rv)
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    a = np.where(small, 1.0, np.sin(safe) / safe)
    b = np.where(small, 0.5, (1.0 - np.cos(safe)) / safe**2)
    return np.eye(3) + a * k + b * (k @ k)


def rotation_vector_from_matrix(r: FloatArray) -> FloatArray:
    """Rotation vector (axis times angle in [0, pi] [rad]) of one rotation matrix.

    Args:
        r: Rotation matrix, shape (3, 3).

    Returns:
        Rotation vector, shape (3,).
    """
    cos = min(max((float(np.trace(r)) - 1.0) / 2.0, -1.0), 1.0)
    angle = float(np.arccos(cos))
    axis = np.array((r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]))
    norm = float(np.linalg.norm(axis))
    if angle < 1e-8:
        return np.zeros(3)
    if np.pi - angle < 1e-6 or norm < 1e-9:
        # Near a half turn: the axis is the eigenvector of the symmetric part.
        values, vectors = np.linalg.eigh((r + r.T) / 2.0)
        return np.asarray(vectors[:, int(np.argmax(values))] * angle, dtype=float)
    return np.asarray(axis / norm * angle, dtype=float)


def interpolate_frames(
    start: FloatArray, end: FloatArray, progress: FloatArray
) -> FloatArray:
    """Frames on the geodesic from ``start`` to ``end`` (slerp), at ``progress``.

    Args:
        start: Rotation matrix at progress 0, shape (3, 3).
        end: Rotation matrix at progress 1, shape (3, 3).
        progress: Fractions of the way, shape (n,).

    Returns:
        Rotation matrices start @ exp(progress log(start^T end)), shape (n, 3, 3).
    """
    step = rotation_vector_from_matrix(start.T @ end)
    return start @ matrix_from_rotation_vector(progress[:, None] * step)


def rotation_angle(start: FloatArray, end: FloatArray) -> float:
    """Angle of the rotation taking frame ``start`` to frame ``end`` [rad]."""
    return float(np.linalg.norm(rotation_vector_from_matrix(start.T @ end)))


def quaternion_from_matrix(r: FloatArray) -> FloatArray:
    """Unit quaternions (w, x, y, z), w >= 0, of rotation matrices.

    Args:
        r: Rotation matrices, shape (n, 3, 3).

    Returns:
        Quaternions, shape (n, 4).
    """
    m = np.asarray(r, dtype=float)
    trace = m[:, 0, 0] + m[:, 1, 1] + m[:, 2, 2]
    # Largest of 4w^2, 4x^2, 4y^2, 4z^2 picks a well-conditioned formula.
    squares = np.stack(
        (
            1.0 + trace,
            1.0 + m[:, 0, 0] - m[:, 1, 1] - m[:, 2, 2],
            1.0 - m[:, 0, 0] + m[:, 1, 1] - m[:, 2, 2],
            1.0 - m[:, 0, 0] - m[:, 1, 1] + m[:, 2, 2],
        ),
        axis=1,
    )
    pick = np.argmax(squares, axis=1)
    s = np.sqrt(np.maximum(squares[np.arange(len(m)), pick], _EPS))
    d = {
        "w": m[:, 2, 1] - m[:, 1, 2],
        "x": m[:, 0, 2] - m[:, 2, 0],
        "y": m[:, 1, 0] - m[:, 0, 1],
        "xy": m[:, 0, 1] + m[:, 1, 0],
        "xz": m[:, 0, 2] + m[:, 2, 0],
        "yz": m[:, 1, 2] + m[:, 2, 1],
    }
    q = np.empty((len(m), 4))
    cases = (
        (s, d["w"] / s, d["x"] / s, d["y"] / s),
        (d["w"] / s, s, d["xy"] / s, d["xz"] / s),
        (d["x"] / s, d["xy"] / s, s, d["yz"] / s),
        (d["y"] / s, d["xz"] / s, d["yz"] / s, s),
    )
    for index, case in enumerate(cases):
        rows = pick == index
        q[rows] = np.stack([c[rows] for c in case], axis=1) / 2.0
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 0] < 0] *= -1.0
    return q


def matrix_from_quaternion(q: FloatArray) -> FloatArray:
    """Rotation matrices of quaternions (w, x, y, z), normalised first.

    Args:
        q: Quaternions, shape (n, 4).

    Returns:
        Rotation matrices, shape (n, 3, 3).
    """
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    rows = (
        (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    )
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def unit(v: FloatArray) -> FloatArray:
    """Vectors scaled to unit length, shape (..., 3); zero vectors stay zero."""
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.asarray(v / np.maximum(norm, _EPS), dtype=float)
