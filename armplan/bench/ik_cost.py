"""Per-target and per-point cost of the IK, beside two peers on the same targets.

- scipy's SLSQP: minimises the same measure (TPE) over the same active joints
  subject to the same wrist target, from the same start posture: a plain
  ``scipy.optimize.minimize(method="SLSQP")`` IK, as a user without armplan
  might write it.
- ikpy: ``Chain.inverse_kinematics`` on the project's URDF from the same
  start posture (:mod:`armplan.bench.ikpy_peer`). It only puts the wrist on
  target and minimises no measure: less work than ours.

All three run on the same targets in the same process, each first called
once untimed on one more target: a cold first call (ikpy's took 413 ms
against a 47 ms median over 12 targets) would otherwise weigh on the mean
and the p99.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import partial
from typing import Any, NamedTuple

import numpy as np
from scipy.optimize import minimize  # type: ignore[import-untyped]

from armplan.bench import ikpy_peer
from armplan.bench.extras import require
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
#: eq. 14 steps timed in a row per target (the figure is per step).
STEPS = 20


class IKCost(NamedTuple):
    """Results of the IK benchmark.

    Attributes:
        ours: Time per target of ``services.ik.solve`` [s].
        peer: Time per target of the SLSQP IK [s].
        step: Time of one eq. 14 step, the cost per path point [s].
        ours_reached: Fraction of targets our IK reached within 0.1 mm.
        peer_reached: Fraction of targets the peer reached within 0.1 mm.
        tpe_gap: Mean TPE of ours minus the peer's, on targets both reached [J].
        ikpy: Time per target of ikpy's IK [s].
        ikpy_reached: Fraction of targets ikpy reached within 0.1 mm.
        both: Which targets ours and SLSQP both reached, shape (n,): SLSQP
            spends most of its time failing (300 iterations), so its ratio
            on these alone is the like-for-like one.
        load_average: The machine's 1-minute load average at the start and
            the end of this benchmark (runnable processes; compare with its
            CPUs).
    """

    ours: Timing
    peer: Timing
    step: Timing
    ours_reached: float
    peer_reached: float
    tpe_gap: float
    ikpy: Timing
    ikpy_reached: float
    both: np.ndarray
    load_average: tuple[float, float]

    def figures(self) -> dict[str, float]:
        """The JSON figures of ``armplan bench`` [ms, us, J]; ratios peer / ours."""
        ours = self.ours.mean
        return {
            "targets": float(len(self.ours.samples)),
            "ik_load_average_start": self.load_average[0],
            "ik_load_average_end": self.load_average[1],
            "ik_per_target_ms": ours * 1e3,
            "ik_per_target_p99_ms": self.ours.percentile(99) * 1e3,
            "slsqp_per_target_ms": self.peer.mean * 1e3,
            "speedup_vs_slsqp": self.peer.mean / ours,
            "common_targets": float(self.both.sum()),
            "ik_per_common_target_ms": _mean_ms(self.ours, self.both),
            "slsqp_per_common_target_ms": _mean_ms(self.peer, self.both),
            "speedup_vs_slsqp_on_common": _mean_ms(self.peer, self.both)
            / _mean_ms(self.ours, self.both),
            "ikpy_per_target_ms": self.ikpy.mean * 1e3,
            "speedup_vs_ikpy": self.ikpy.mean / ours,
            "gpm_step_per_point_us": self.step.mean / STEPS * 1e6,
            "ik_reached_fraction": self.ours_reached,
            "slsqp_reached_fraction": self.peer_reached,
            "ikpy_ik_reached_fraction": self.ikpy_reached,
            "tpe_gap_on_common_targets_j": self.tpe_gap,
        }


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
    """Time ours and both peers on ``n`` reachable targets of the right arm.

    ``after`` runs after each of the ``steps(n)`` timed calls, untimed (progress).
    """
    require("ikpy")
    load_start = os.getloadavg()[0]
    arm = load_arm("right")
    tpe = TotalPotentialEnergy(MeasureParams().mu)
    targets = _targets(arm, n + 1, seed)
    warm = targets.pop()  # the first n are the same for every n
    start = rest(arm.side)
    chain = ikpy_peer.wrist_chain(arm)
    runs = {t.tobytes(): StepRun(arm, tpe, t) for t in [warm, *targets]}
    solvers: list[Callable[[np.ndarray], object]] = [
        lambda t: solve(arm, t, primitive="S_R E_PR W_P").q,
        lambda t: slsqp_ik(arm, t, tpe),
        lambda t: runs[t.tobytes()].steps(),
        lambda t: ikpy_peer.ikpy_track(chain, t[None], start)[0],
    ]
    timings, (ours_q, peer_q, _, ikpy_q) = _time_interleaved(
        solvers, targets, after, warm
    )
    ours, peer, step, ikpy = timings
    ours_ok = _reached(arm, ours_q, targets)
    peer_ok = _reached(arm, peer_q, targets)
    both = ours_ok & peer_ok
    gaps = [
        tpe.value(chain_for(arm).state(a)) - tpe.value(chain_for(arm).state(b))
        for a, b, ok in zip(ours_q, peer_q, both, strict=True)
        if ok
    ]
    gap = float(np.mean(gaps)) if gaps else float("nan")
    ikpy_ok = _reached(arm, ikpy_q, targets)
    return IKCost(
        ours,
        peer,
        step,
        float(ours_ok.mean()),
        float(peer_ok.mean()),
        gap,
        ikpy,
        float(ikpy_ok.mean()),
        both,
        (load_start, os.getloadavg()[0]),
    )


def _time_interleaved(
    solvers: list[Callable[[np.ndarray], object]],
    targets: list[np.ndarray],
    after: Callable[[], object] | None,
    warm: np.ndarray,
) -> tuple[list[Timing], list[list[Any]]]:
    """Time every solver on each target in turn, target by target.

    Every solver first runs once on ``warm``, untimed, its result dropped:
    a cold first call (imports, caches) is not one of the samples.
    Interleaved, a change of the machine's load during the run slows ours
    and the peers alike, so their ratios hold.

    Returns:
        Per solver, its times [s] and its results on ``targets`` (postures
        [rad], (5,) each).
    """
    for solver in solvers:  # warm-up, untimed
        solver(warm)
    solved: list[list[Any]] = [[] for _ in solvers]

    def call(k: int, target: np.ndarray) -> None:
        solved[k].append(solvers[k](target))

    calls: list[Callable[[], object]] = [
        partial(call, k, t) for t in targets for k in range(len(solvers))
    ]
    samples = time_calls(calls, after).samples
    stride = len(solvers)
    return [Timing(samples[k::stride]) for k in range(stride)], solved


def steps(n: int) -> int:
    """How many timed calls ``run(n)`` makes (for a progress bar)."""
    return 4 * n


class StepRun:
    """``STEPS`` eq. 14 steps in a row towards one target, from the rest posture.

    As the tracker takes them, one per path point: the task residual and the
    measure's gradient at the current state, the step, the new posture and
    its state (the next step's). The start (the rest posture and its state)
    is made once, untimed, so a timed ``steps`` is ``STEPS`` steps and
    nothing else. (One step alone, between 50 ms SLSQP calls, ran with cold
    caches: 62-93 us against 18 us in a row.)
    """

    def __init__(
        self, arm: ArmModel, tpe: TotalPotentialEnergy, target: np.ndarray
    ) -> None:
        self.chain = chain_for(arm)
        self.tpe = tpe
        self.task = WristTask.make(target.tolist(), None, arm.side.sign)
        self.start = list(rest(arm.side))
        self.state = self.chain.state(self.start)

    def steps(self) -> list[float]:
        """Take ``STEPS`` steps from the start; the posture they end at [rad]."""
        chain, q, st = self.chain, self.start, self.state
        for _ in range(STEPS):
            err, cols = self.task.residual(st)
            dq = gpm_step(
                q,
                err,
                cols,
                self.tpe.gradient(st),
                ACTIVE_JOINTS,
                chain.lower,
                chain.upper,
                1.0,
                0.2,
                0.05,
            ).dq
            q = [q[k] + dq[k] for k in range(len(q))]
            st = chain.state(q)
        return q


def _mean_ms(timing: Timing, mask: np.ndarray) -> float:
    """Mean of ``timing``'s samples where ``mask`` [ms] (NaN if none)."""
    chosen = timing.samples[mask]
    return float(chosen.mean() * 1e3) if len(chosen) else float("nan")


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
