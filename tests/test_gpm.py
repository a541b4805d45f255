"""The gradient projection step (eq. 14): projector identities and joint limits."""

from __future__ import annotations

import numpy as np
from conftest import random_posture

from services.ik.gpm import decompose, gpm_step
from services.ik.measures import TotalPotentialEnergy
from shared.robot import ArmModel


def test_projector_identities(rng: np.random.Generator) -> None:
    """N is idempotent, symmetric, J N = 0, and J J+ J = J for full-rank J."""
    for m, n in [(3, 4), (3, 5), (4, 5), (3, 3)]:
        jac = rng.normal(size=(m, n)) * 0.1
        d = decompose(jac)
        np.testing.assert_allclose(d.null @ d.null, d.null, atol=1e-12)
        np.testing.assert_allclose(d.null, d.null.T, atol=1e-12)
        np.testing.assert_allclose(jac @ d.null, 0.0, atol=1e-12)
        np.testing.assert_allclose(jac @ d.pinv @ jac, jac, atol=1e-4)


def test_rank_deficient_jacobian_keeps_its_null_space(rng: np.random.Generator) -> None:
    """For a rank-2 J (3x3) the projector keeps exactly one direction."""
    a = rng.normal(size=(3, 2))
    jac = a @ rng.normal(size=(2, 3))
    d = decompose(jac)
    assert round(float(np.trace(d.null))) == 1
    np.testing.assert_allclose(jac @ d.null, 0.0, atol=1e-12)


def test_null_space_motion_leaves_the_wrist_still(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """With zero task error, a small GPM step moves the wrist only to second order."""
    measure = TotalPotentialEnergy(0.03)
    for _ in range(30):
        q = random_posture(arm, rng)
        q = np.clip(q, arm.limits.lower + 0.3, arm.limits.upper - 0.3)
        kin = arm.kinematics(q)
        step = gpm_step(
            q,
            np.zeros(3),
            kin.wrist_jacobian,
            measure.gradient(kin),
            np.arange(4),
            arm.limits,
            alpha=0.05,
            max_step=0.2,
            max_null_step=1e-3,
        )
        moved = np.linalg.norm(arm.fk(q + step.dq).wrist - kin.wrist)
        assert moved < 1e-6
        assert np.abs(kin.wrist_jacobian @ step.dq).max() < 1e-9


def test_null_space_motion_descends_h(arm: ArmModel, rng: np.random.Generator) -> None:
    """A small null-space step lowers H (it follows -N grad H)."""
    measure = TotalPotentialEnergy(0.03)
    for _ in range(30):
        q = np.clip(
            random_posture(arm, rng), arm.limits.lower + 0.3, arm.limits.upper - 0.3
        )
        kin = arm.kinematics(q)
        step = gpm_step(
            q,
            np.zeros(3),
            kin.wrist_jacobian,
            measure.gradient(kin),
            np.arange(4),
            arm.limits,
            alpha=0.05,
            max_step=0.2,
            max_null_step=1e-3,
        )
        if np.abs(step.projected_gradient).max() > 1e-6:
            assert measure.value(arm.kinematics(q + step.dq)) < measure.value(kin)


def test_steps_never_leave_the_joint_limits(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Large task errors and gains near the limits still give postures in range."""
    measure = TotalPotentialEnergy(0.03)
    for _ in range(300):
        q = random_posture(arm, rng)
        edge = rng.integers(0, 5)
        q[edge] = (
            arm.limits.lower[edge] if rng.random() < 0.5 else arm.limits.upper[edge]
        )
        kin = arm.kinematics(q)
        step = gpm_step(
            q,
            rng.normal(size=3) * 0.2,
            kin.wrist_jacobian,
            measure.gradient(kin),
            np.arange(5),
            arm.limits,
            alpha=100.0,
            max_step=0.5,
            max_null_step=0.5,
        )
        assert arm.limits.contains(q + step.dq)


def test_inactive_joints_do_not_move(arm: ArmModel, rng: np.random.Generator) -> None:
    """Only the primitive's active joints change."""
    measure = TotalPotentialEnergy(0.03)
    q = np.clip(
        random_posture(arm, rng), arm.limits.lower + 0.3, arm.limits.upper - 0.3
    )
    kin = arm.kinematics(q)
    step = gpm_step(
        q,
        np.array([0.01, 0.0, -0.01]),
        kin.wrist_jacobian,
        measure.gradient(kin),
        np.array([0, 2]),
        arm.limits,
        alpha=1.0,
        max_step=0.2,
        max_null_step=0.05,
    )
    assert step.dq[[1, 3, 4]].tolist() == [0.0, 0.0, 0.0]
    assert np.abs(step.dq[[0, 2]]).max() > 0
