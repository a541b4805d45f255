"""The gradient projection step (eq. 14): projector identities and joint limits."""

from __future__ import annotations

import numpy as np
from conftest import random_posture

from services.ik.gpm import gpm_step
from services.ik.kernel import chain_for
from services.ik.kernel.small import NormalSolver, NormalSolver3
from services.ik.measures import TotalPotentialEnergy
from services.ik.task import WristTask
from shared.robot import ArmModel


def _pinv(
    cols: list[tuple[float, ...]], free: list[int], damping: float = 0.0
) -> np.ndarray:
    """J+ as a matrix (free joints x rows), column by column from apply()."""
    solver = NormalSolver(cols, free, damping, 1e-8)
    m = len(cols[0])
    return np.array([solver.apply(e) for e in np.eye(m)]).T


def test_pseudo_inverse_identities(rng: np.random.Generator) -> None:
    """Undamped: J J+ = I for full-row-rank J, and J+ matches numpy's pinv."""
    for m, n in [(2, 4), (3, 4), (3, 5), (4, 5), (3, 3)]:
        jac = rng.normal(size=(m, n)) * 0.1
        cols = [tuple(c) for c in jac.T]
        pinv = _pinv(cols, list(range(n)))
        np.testing.assert_allclose(jac @ pinv, np.eye(m), atol=1e-10)
        np.testing.assert_allclose(pinv, np.linalg.pinv(jac), atol=1e-9)


def test_unrolled_solver_agrees_with_the_generic_one(rng: np.random.Generator) -> None:
    """The 3-row solver gives the generic solver's J+ v and J x."""
    for _ in range(50):
        jac = rng.normal(size=(3, 5)) * 0.1
        cols = [tuple(c) for c in jac.T]
        free = sorted(rng.choice(5, size=rng.integers(3, 6), replace=False).tolist())
        v, x = rng.normal(size=3), rng.normal(size=5)
        fast, slow = (
            NormalSolver3(cols, free, 0.0, 1e-8),
            NormalSolver(cols, free, 0.0, 1e-8),
        )
        np.testing.assert_allclose(fast.apply(v), slow.apply(v), atol=1e-12)
        np.testing.assert_allclose(fast.times(x), slow.times(x), atol=1e-15)


def test_projector_from_the_solver_is_exact(rng: np.random.Generator) -> None:
    """N = I - J+ J is idempotent and J N = 0 (the undamped projector)."""
    for m, n in [(3, 4), (3, 5), (4, 5), (2, 4)]:
        jac = rng.normal(size=(m, n)) * 0.1
        null = np.eye(n) - _pinv([tuple(c) for c in jac.T], list(range(n))) @ jac
        np.testing.assert_allclose(null @ null, null, atol=1e-10)
        np.testing.assert_allclose(jac @ null, 0.0, atol=1e-12)


def test_damping_keeps_near_singular_steps_bounded() -> None:
    """A nearly rank-deficient J gives a bounded J+ v (damped below the floor)."""
    cols = [(0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, 0.0, 1e-7), (0.0, 0.0, 0.0)]
    step = NormalSolver(cols, [0, 1, 2, 3], 0.0, 1e-8).apply([0.0, 0.0, 1e-3])
    assert max(abs(v) for v in step) < 20.0  # undamped it would be 1e4 rad


def _step(
    arm: ArmModel,
    q: np.ndarray,
    error: list[float],
    active: tuple[int, ...],
    **kw: float,
):  # type: ignore[no-untyped-def]
    chain = chain_for(arm)
    st = chain.state(q)
    measure = TotalPotentialEnergy(0.03)
    _, cols = WristTask.make(st.wrist, None, arm.side.sign).residual(st)
    options = {"alpha": 0.05, "max_step": 0.2, "max_null_step": 1e-3} | kw
    step = gpm_step(
        list(q), error, cols, measure.gradient(st), active, chain.lower, chain.upper,
        options["alpha"], options["max_step"], options["max_null_step"],
    )  # fmt: skip
    return st, np.array(cols).T, np.array(step.dq), step, measure


def test_null_space_motion_leaves_the_wrist_still(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """With zero task error a GPM step is in J's null space: J dq = 0."""
    for _ in range(30):
        q = np.clip(
            random_posture(arm, rng), arm.limits.lower + 0.3, arm.limits.upper - 0.3
        )
        st, jac, dq, _, _ = _step(arm, q, [0.0, 0.0, 0.0], (0, 1, 2, 3))
        assert np.abs(jac @ dq).max() < 1e-12
        moved = np.linalg.norm(chain_for(arm).state(q + dq).wrist - st.wrist)
        assert moved < 1e-6


def test_null_space_motion_descends_h(arm: ArmModel, rng: np.random.Generator) -> None:
    """A small null-space step lowers H (it follows -N grad H)."""
    chain = chain_for(arm)
    for _ in range(30):
        q = np.clip(
            random_posture(arm, rng), arm.limits.lower + 0.3, arm.limits.upper - 0.3
        )
        st, _, dq, step, measure = _step(arm, q, [0.0, 0.0, 0.0], (0, 1, 2, 3))
        if max(abs(p) for p in step.projected_gradient) > 1e-6:
            assert measure.value(chain.state(q + dq)) < measure.value(st)


def test_steps_never_leave_the_joint_limits(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Large task errors and gains at the limits still give postures in range."""
    for _ in range(300):
        q = random_posture(arm, rng)
        edge = rng.integers(0, 5)
        q[edge] = (
            arm.limits.lower[edge] if rng.random() < 0.5 else arm.limits.upper[edge]
        )
        error = list(rng.normal(size=3) * 0.2)
        _, _, dq, _, _ = _step(
            arm, q, error, (0, 1, 2, 3, 4), alpha=100.0, max_step=0.5, max_null_step=0.5
        )
        assert arm.limits.contains(q + dq)


def test_inactive_joints_do_not_move(arm: ArmModel, rng: np.random.Generator) -> None:
    """Only the primitive's active joints change."""
    q = np.clip(
        random_posture(arm, rng), arm.limits.lower + 0.3, arm.limits.upper - 0.3
    )
    _, _, dq, _, _ = _step(
        arm, q, [0.01, 0.0, -0.01], (0, 2), alpha=1.0, max_null_step=0.05
    )
    assert dq[[1, 3, 4]].tolist() == [0.0, 0.0, 0.0]
    assert np.abs(dq[[0, 2]]).max() > 0
