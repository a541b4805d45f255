"""Per-target and per-point cost of the IK, beside scipy's SLSQP on the same work.

The peer minimises the same measure (TPE) over the same active joints subject
to the same wrist target, from the same start posture: a plain
``scipy.optimize.minimize(method="SLSQP")`` IK, as a user without armplan
might write it. Both run on the same targets in the same process.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy.optimize import minimize

from armplan.bench.timer import Timing, time_calls
from services.ik import solve
from services.ik.gpm import gpm_step
from services.ik.kernel import chain_for
from services.ik.measures import MeasureParams, TotalPotentialEnergy
from services.ik.task import WristTask
from shared.robot import ArmModel, load_arm
from shared.robot.postures import rest

ACTIVE = np.arange(4)  # S_R E_PR W_P: the full reaching primitive
ACTIVE_JOINTS = (0, 1, 2, 3)


class IKCost(NamedTuple):
    """Results of the IK benchmark.

    Attributes:
        ours: Time per target of ``services.ik.solve`` [s].
        peer: Time per target of the SLSQP IK [s].
        step: Time of one eq. 14 step, the cost per path point [s].
        ours_reached: Fraction of targets our IK reached within 0.1 mm.
        peer_reached: Fraction of targets the peer reached within 0.1 mm.
        tpe_gap: Mean TPE of ours minus the peer's, on targets both reached [J].
    """

    ours: Timing
    peer: Timing
    step: Timing
    ours_reached: float
    peer_reached: float
    tpe_gap: float


def _targets(arm: ArmModel, n: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [
        arm.fk(rng.uniform(arm.limits.lower, arm.limits.upper)).wrist for _ in range(n)
    ]


def slsqp_ik(
    arm: ArmModel, target: np.ndarray, tpe: TotalPotentialEnergy
) -> np.ndarray:
    """The peer: minimise TPE over the first four joints with the wrist on target."""
    start = rest(arm.side)
    chain = chain_for(arm)

    def posture(x: np.ndarray) -> np.ndarray:
        return np.append(x, start[4])

    result = minimize(
        lambda x: tpe.value(chain.state(posture(x))),
        start[ACTIVE],
        jac=lambda x: np.array(tpe.gradient(chain.state(posture(x))))[ACTIVE],
        method="SLSQP",
        constraints=[
            {
                "type": "eq",
                "fun": lambda x: arm.fk(posture(x)).wrist - target,
                "jac": lambda x: arm.jacobian(posture(x), "wrist")[:, ACTIVE],
            }
        ],
        bounds=list(
            zip(arm.limits.lower[ACTIVE], arm.limits.upper[ACTIVE], strict=True)
        ),
        options={"maxiter": 300, "ftol": 1e-10},
    )
    return posture(result.x)


def run(
    n: int = 100, seed: int = 7, after: Callable[[], object] | None = None
) -> IKCost:
    """Time both IKs on ``n`` reachable targets of the right arm.

    ``after`` runs after each of the ``3 n`` timed calls, untimed (progress).
    """
    arm = load_arm("right")
    tpe = TotalPotentialEnergy(MeasureParams().mu)
    targets = _targets(arm, n, seed)
    ours_q: list[np.ndarray] = []
    peer_q: list[np.ndarray] = []
    ours = time_calls(
        [
            lambda t=t: ours_q.append(solve(arm, t, primitive="S_R E_PR W_P").q)
            for t in targets
        ],
        after,
    )
    peer = time_calls(
        [lambda t=t: peer_q.append(slsqp_ik(arm, t, tpe)) for t in targets], after
    )
    step = time_calls([lambda t=t: _one_step(arm, tpe, t) for t in targets], after)
    ours_ok = _reached(arm, ours_q, targets)
    peer_ok = _reached(arm, peer_q, targets)
    both = ours_ok & peer_ok
    gaps = [
        tpe.value(chain_for(arm).state(a)) - tpe.value(chain_for(arm).state(b))
        for a, b, ok in zip(ours_q, peer_q, both, strict=True)
        if ok
    ]
    gap = float(np.mean(gaps)) if gaps else float("nan")
    return IKCost(ours, peer, step, float(ours_ok.mean()), float(peer_ok.mean()), gap)


def _one_step(arm: ArmModel, tpe: TotalPotentialEnergy, target: np.ndarray) -> None:
    """One eq. 14 step from the rest posture, as the tracker does per path point."""
    chain = chain_for(arm)
    q = list(rest(arm.side))
    st = chain.state(q)
    err, cols = WristTask.make(target, None, arm.side.sign).residual(st)
    gpm_step(
        q,
        err,
        cols,
        tpe.gradient(st),
        ACTIVE_JOINTS,
        chain.lower,
        chain.upper,
        1.0,
        0.2,
        0.05,
    )
    chain.state(q)


def _reached(
    arm: ArmModel, postures: list[np.ndarray], targets: list[np.ndarray]
) -> np.ndarray:
    """Mask: which postures put the wrist within 0.1 mm of their target."""
    return np.array(
        [
            np.linalg.norm(arm.fk(q).wrist - t) < 1e-4
            for q, t in zip(postures, targets, strict=True)
        ]
    )
