"""The weighted tracking step: weighted least norm, null space, soft limits."""

from __future__ import annotations

import numpy as np
import pytest

from services.ik.weighted import (
    DAMPING,
    FLOOR,
    LOCKED,
    _parts3,
    _parts_general,
    limit_weight,
    weighted_step,
)

LOW, HIGH = [-3.0] * 5, [3.0] * 5  # far-away limits: the weights stay the base


def _case(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A random posture, Jacobian (3 x 5, arm-like column sizes) and wrist step."""
    rng = np.random.default_rng(seed)
    return (
        rng.uniform(-0.5, 0.5, 5),
        rng.normal(0.0, 0.1, (3, 5)),
        rng.normal(0.0, 0.002, 3),
    )


def _step(
    q: np.ndarray,
    jac: np.ndarray,
    dx: np.ndarray,
    base: list[float],
    gradient: np.ndarray | None = None,
    alpha: float = 0.0,
    low: list[float] = LOW,
    high: list[float] = HIGH,
) -> np.ndarray:
    """weighted_step on numpy inputs (steps uncapped, margin 0.2 rad)."""
    grad = [0.0] * 5 if gradient is None else list(gradient)
    cols = [tuple(c) for c in jac.T]
    args = (list(q), list(dx), cols, grad, list(base), low, high, alpha)
    return np.array(weighted_step(*args, 1.0, 1.0, 0.2))


@pytest.mark.parametrize("seed", range(5))
def test_equals_the_closed_form_weighted_least_norm(seed: int) -> None:
    """dq = W J^T (J W J^T + d I)^-1 dx, computed by numpy, for any weights."""
    q, jac, dx = _case(seed)
    base = [1.0, 1.0, LOCKED, 1.0, LOCKED]
    w = np.diag(base)
    expected = w @ jac.T @ np.linalg.solve(jac @ w @ jac.T + DAMPING * np.eye(3), dx)
    np.testing.assert_allclose(_step(q, jac, dx, base), expected, atol=1e-12)


@pytest.mark.parametrize("seed", range(5))
def test_does_the_task_and_prefers_the_active_joints(seed: int) -> None:
    """J dq = dx (up to the damping), and a locked joint moves less than it
    would if it were free."""
    q, jac, dx = _case(seed)
    for base in ([1.0] * 5, [1.0, 1.0, 1.0, LOCKED, 1.0]):
        dq = _step(q, jac, dx, base)
        smallest = np.linalg.eigvalsh(jac @ np.diag(base) @ jac.T)[0]
        miss = np.linalg.norm(jac @ dq - dx)  # damping: d / (sigma^2 + d) of dx
        assert miss <= DAMPING / (smallest + DAMPING) * np.linalg.norm(dx) + 1e-15
    free = _step(q, jac, dx, [1.0] * 5)
    locked = _step(q, jac, dx, [1.0, 1.0, 1.0, LOCKED, 1.0])
    assert abs(locked[3]) < abs(free[3])


@pytest.mark.parametrize("seed", range(5))
def test_null_space_part_leaves_the_task_and_descends_h(seed: int) -> None:
    """With a gradient, the extra motion does not move the wrist (to the
    damping's order) and goes downhill in H."""
    q, jac, dx = _case(seed)
    gradient = np.random.default_rng(seed + 100).normal(0.0, 1.0, 5)
    for base in ([1.0] * 5, [1.0, 1.0, 1.0, 1.0, LOCKED]):
        plain = _step(q, jac, dx, base)
        with_h = _step(q, jac, dx, base, gradient, alpha=0.01)
        null = with_h - plain
        assert np.linalg.norm(null) > 1e-6
        assert np.linalg.norm(jac @ null) < 1e-3 * np.linalg.norm(null)
        assert gradient @ null < 0.0
        locked = [k for k in range(5) if base[k] != 1.0]
        assert np.all(null[locked] == 0.0)  # only active joints self-move


def test_limit_weight_is_smooth_and_one_sided() -> None:
    """1 far from a limit or moving away; down to FLOOR on it; continuous in
    the share through zero (the joint turning round)."""
    low, high, margin = -1.0, 1.0, 0.2
    assert limit_weight(0.0, 1.0, low, high, margin) == 1.0
    assert limit_weight(0.95, -1.0, low, high, margin) == 1.0  # moving away
    assert limit_weight(1.0, 1.0, low, high, margin) == FLOOR
    assert limit_weight(-1.0, -1.0, low, high, margin) == FLOOR
    shares = np.linspace(-0.2, 0.2, 401)
    weights = np.array([limit_weight(0.9, s, low, high, margin) for s in shares])
    assert np.max(np.abs(np.diff(weights))) < 0.02
    distances = np.linspace(0.0, 0.3, 301)
    along = np.array([limit_weight(1.0 - d, 1.0, low, high, margin) for d in distances])
    assert np.all(np.diff(along) >= 0.0) and along[-1] == 1.0


def test_a_joint_near_its_limit_hands_its_share_over() -> None:
    """The same task step near a limit: the joint heading into it moves less,
    the others more, the task is still done, and no joint leaves its range."""
    q, jac, dx = _case(7)
    dq = _step(q, jac, dx, [1.0] * 5)
    k = int(np.argmax(np.abs(dq)))
    high = list(HIGH)
    low = list(LOW)
    if dq[k] > 0:
        high[k] = q[k] + 0.02
    else:
        low[k] = q[k] - 0.02
    near = _step(q, jac, dx, [1.0] * 5, low=low, high=high)
    assert abs(near[k]) < 0.5 * abs(dq[k])
    np.testing.assert_allclose(jac @ near, dx, atol=0.05 * np.linalg.norm(dx))
    assert np.all(q + near <= np.array(high)) and np.all(q + near >= np.array(low))


@pytest.mark.parametrize("alpha", [0.0, 0.7])
def test_the_unrolled_three_row_step_is_the_general_one_bit_for_bit(
    alpha: float,
) -> None:
    """The wrist-position fast path (``_parts3``) and the general solver path
    give identical floats, with locked, limit-weighted and zero columns."""
    rng = np.random.default_rng(11)
    for i in range(400):
        cols = [tuple(float(v) for v in c) for c in rng.normal(0.0, 0.1, (5, 3))]
        if i % 7 == 0:
            cols[2] = (0.0, 0.0, 0.0)  # a joint that does not move the wrist
        error = [float(v) for v in rng.normal(0.0, 0.01, 3)]
        gradient = [float(v) for v in rng.normal(0.0, 1.0, 5)]
        base = [1.0 if rng.random() < 0.6 else LOCKED for _ in range(5)]
        base[int(rng.integers(5))] = 1.0  # a primitive moves at least one joint
        weights = [b * float(rng.uniform(FLOOR, 1.0)) for b in base]
        args = (error, cols, gradient, weights, base, alpha)
        assert _parts3(*args) == _parts_general(*args)


@pytest.mark.parametrize("rows", [3, 4])
def test_no_self_motion_without_more_active_joints_than_rows(rows: int) -> None:
    """As many active joints as task rows leave no null space, even where
    their columns lose rank (a singular posture): the gradient then adds
    nothing, where a damped inverse would let it leak into the task's weak
    direction."""
    rng = np.random.default_rng(21)
    active = [0, 1, 2, 4][:rows] if rows == 4 else [0, 2, 4]
    base = [1.0 if k in active else LOCKED for k in range(5)]
    for singular in (False, True):
        jac = rng.normal(0.0, 0.1, (rows, 5))
        if singular:
            jac[:, active[-1]] = 0.5 * jac[:, active[0]]
        q, dx = rng.uniform(-0.5, 0.5, 5), rng.normal(0.0, 0.002, rows)
        gradient = rng.normal(0.0, 1.0, 5)
        plain = _step(q, jac, dx, base)
        np.testing.assert_array_equal(_step(q, jac, dx, base, gradient, 0.7), plain)
