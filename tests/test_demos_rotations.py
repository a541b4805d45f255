"""The demonstration code's rotations: identities, round trips, and the
reach model's pointing error against the frames interpolated directly."""

from __future__ import annotations

import math

import numpy as np

from shared.demos.anthropometry import draw_subjects
from shared.demos.arm_pose import ArmPose
from shared.demos.reach_model import pointing_error
from shared.demos.rotations import (
    interpolate_frames,
    matrix_from_rotation_vector,
    rotation_vector_from_matrix,
    skew,
)


def test_skew_is_the_cross_product_on_stacks() -> None:
    rng = np.random.default_rng(3)
    v, w = rng.normal(size=(4, 5, 3)), rng.normal(size=(4, 5, 3))
    k = skew(v)
    assert k.shape == (4, 5, 3, 3)
    np.testing.assert_allclose((k @ w[..., None])[..., 0], np.cross(v, w), atol=1e-15)
    np.testing.assert_array_equal(k, -np.swapaxes(k, -1, -2))


def test_rotation_vectors_round_trip_through_matrices() -> None:
    rng = np.random.default_rng(4)
    axes = rng.normal(size=(200, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    vectors = axes * rng.uniform(0.0, math.pi - 1e-3, size=(200, 1))
    matrices = matrix_from_rotation_vector(vectors)
    np.testing.assert_allclose(
        matrices @ np.swapaxes(matrices, -1, -2),
        np.broadcast_to(np.eye(3), (200, 3, 3)),
        atol=1e-14,
    )
    np.testing.assert_allclose(np.linalg.det(matrices), 1.0, atol=1e-14)
    for vector, matrix in zip(vectors, matrices, strict=True):
        np.testing.assert_allclose(
            rotation_vector_from_matrix(matrix), vector, atol=1e-9
        )
        np.testing.assert_array_equal(matrix_from_rotation_vector(vector), matrix)


def test_the_pointing_error_is_the_angle_between_the_interpolated_wrists() -> None:
    """The reach model's error, from frames interpolated by ``interpolate_frames``."""
    rng = np.random.default_rng(5)
    subject = draw_subjects(1, rng)[0]
    for _ in range(20):
        start, goal = (
            ArmPose(matrix_from_rotation_vector(rng.normal(size=3)), b, 0.0)
            for b in rng.uniform(0.2, 2.0, size=2)
        )
        shape = np.array(
            (
                subject.upper_arm + subject.forearm * math.cos(goal.flexion),
                0.0,
                -subject.forearm * math.sin(goal.flexion),
            )
        )
        for progress in (0.0, 0.3, 0.7, 1.0):
            now, end = (
                interpolate_frames(start.frame, goal.frame, np.array([progress, 1.0]))
                @ shape
            )
            cos = now @ end / (np.linalg.norm(now) * np.linalg.norm(end))
            expected = math.acos(min(max(float(cos), -1.0), 1.0))
            assert abs(pointing_error(start, goal, progress, subject) - expected) < 1e-7
