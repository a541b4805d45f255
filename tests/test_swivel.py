"""The elbow swivel angle and its gradient."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import random_posture

from services.ik.kernel import chain_for
from shared.geometry import swivel_angle, swivel_gradient
from shared.robot import ArmModel, load_arm
from shared.robot.postures import mirror

S = np.zeros(3)


@pytest.mark.parametrize(
    "elbow,expected",
    [
        ((0.1, 0.0, -0.05), math.pi),  # wrist forward, elbow below: hanging
        ((0.1, 0.0, 0.05), 0.0),  # elbow above the axis
        ((0.1, -0.05, 0.0), math.pi / 2),  # right: +90 deg about the forward axis
        ((0.1, 0.05, 0.0), 3 * math.pi / 2),  # left
    ],
)
def test_swivel_of_known_arm_planes(
    elbow: tuple[float, float, float], expected: float
) -> None:
    """With the wrist straight ahead, phi measures the elbow's direction from up."""
    assert swivel_angle(S, np.array(elbow), np.array([0.2, 0.0, 0.0])) == pytest.approx(
        expected
    )


def test_swivel_is_undefined_for_a_straight_arm() -> None:
    """On the shoulder-wrist axis the angle falls back to pi, gradient zero."""
    e, w = np.array([0.1, 0.0, 0.0]), np.array([0.2, 0.0, 0.0])
    assert swivel_angle(S, e, w) == math.pi
    cols = [(1.0, 1.0, 1.0)] * 5
    assert not any(swivel_gradient(S, e, w, cols, cols))


def test_mirrored_arms_have_mirrored_swivel(rng: np.random.Generator) -> None:
    """phi_left = 2 pi - phi_right: the spring energy (pi - phi)^2 is the same."""
    right, left = load_arm("right"), load_arm("left")
    for _ in range(100):
        q = random_posture(right, rng)
        a = swivel_angle(*right.fk(q)[:3])
        b = swivel_angle(*left.fk(mirror(q))[:3])
        assert (a + b) % (2 * math.pi) == pytest.approx(
            0.0, abs=1e-9
        ) or a + b == pytest.approx(2 * math.pi)


def test_swivel_gradient_matches_finite_differences(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """d(phi)/dq by the chain rule equals central differences (away from the wrap)."""
    h = 1e-6
    checked = 0
    while checked < 100:
        q = random_posture(arm, rng)
        p = arm.fk(q)
        phi = swivel_angle(*p[:3])
        if (
            min(phi, 2 * math.pi - phi) < 0.1
            or np.linalg.norm(np.cross(p.elbow - p.shoulder, p.wrist - p.shoulder))
            < 1e-3
        ):
            continue  # near the wrap-around or a straight arm
        kin = chain_for(arm).state(q)
        grad = swivel_gradient(kin.shoulder, kin.elbow, kin.wrist, kin.je, kin.jw)
        fd = [
            (
                swivel_angle(*arm.fk(q + h * e)[:3])
                - swivel_angle(*arm.fk(q - h * e)[:3])
            )
            / (2 * h)
            for e in np.eye(5)
        ]
        np.testing.assert_allclose(grad, fd, atol=1e-6)
        checked += 1
