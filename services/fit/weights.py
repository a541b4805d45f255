"""The IK measures' weights mu and omega, by regression on the demonstrations.

The paper sets the swivel spring's stiffness mu (eq. 17) and says the wrist
discomfort weight omega (eq. 19) "can be obtained by multiple regression
methods", without saying of what on what. Here both come from one linear
regression, the reading that needs no other assumption than the method's
own: a demonstrator's posture is the optimum of the IK's measure

    H = GPE + mu EPE_1 + omega WD_1

(GPE the arm's gravitational energy, eq. 16; EPE_1 the swivel spring's
energy and WD_1 the wrist discomfort (theta_wa - theta_N,wa)^2, each per
unit weight, eq. 17-19) among the postures that hold the same wrist
position and palm roll. At such an optimum the gradient projection method
(eq. 14) stops: the gradient of H has no part along the task's null space,
N^T grad H = 0, with N a basis of the null space of the task's Jacobian
(wrist position and palm roll: 4 rows for NAO's 5 joints, one direction).
That is linear in the weights,

    N^T grad GPE + mu N^T grad EPE_1 + omega N^T grad WD_1 = 0,

one equation per sample; the weights are the non-negative least-squares
solution over all samples (scipy's ``nnls``; a negative stiffness would not
be a comfort measure). ``explained`` says how far the two weights account
for the gravity term's unbalance: 1 - |residual| / |N^T grad GPE| (1: the
postures are exactly optimal for the fitted H; 0: the weights explain
nothing of it).

A demonstration without the wrist's roll gives the position task only (two
null directions) and no sight of WristYaw, so no equation for omega; if
none has the roll, omega is not fitted (``None``) and the IK keeps the
shipped weight.

Samples: every ``STRIDE``-th of each trial, turned into NAO joint angles
(``shared.demos.posture_from_points``). A sample is left out where a joint
lies within ``EDGE`` of its limit (there the limit holds the posture, not
the measure) or where no posture within the ranges puts NAO's arm on the
retargeted points (``MISS``).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from services.ik.kernel.chain import Chain, chain_for
from services.ik.measures.tpe import TotalPotentialEnergy
from services.ik.task import WristTask
from shared.demos.posture_from_points import joint_path_from_points
from shared.demos.trial import DemoSet, Trial
from shared.errors import InvalidInputError
from shared.messages.measure_params import MOST, MeasureParams
from shared.messages.motion_model import FittedWeights
from shared.robot.arm_model import ArmModel, load_arm

#: Every STRIDE-th sample of a trial is used (100 Hz demonstrations: 12.5 Hz).
STRIDE = 8
#: A sample with a joint this close to a limit is left out [rad].
EDGE = 0.02
#: A sample whose NAO posture misses the retargeted elbow or wrist by more
#: than this, or the palm's roll by more than ``MISS_ROLL``, is left out [m].
MISS = 0.005
#: See ``MISS`` [rad].
MISS_ROLL = 0.05
#: Singular values below this fraction of the largest count as zero.
RANK_TOL = 1e-9
#: WristYaw's index in the joint vector.
WRIST_YAW = 4


def fit_weights(
    demos: DemoSet,
    *,
    stride: int = STRIDE,
    progress: Callable[[int, int], None] | None = None,
) -> FittedWeights | None:
    """mu and omega under which the demonstrated postures are the IK's optima.

    ``None`` if no sample can be used (every one has a joint at its limit or
    lies outside NAO's ranges): the model then carries no weights and the IK
    uses the shipped ones.

    Args:
        demos: Retargeted demonstrations.
        stride: Use every ``stride``-th sample of each trial (>= 1).
        progress: Told after each trial.

    Raises:
        InvalidInputError: a stride below 1.
    """
    if stride < 1:
        raise InvalidInputError(f"stride must be >= 1, got {stride}", field="stride")
    rows: list[np.ndarray] = []
    for done, trial in enumerate(demos.trials, start=1):
        rows.extend(trial_rows(trial, stride))
        if progress is not None:
            progress(done, len(demos.trials))
    if not rows:
        return None
    oriented = any(t.wrist_frame is not None for t in demos.trials)
    return regress(np.concatenate(rows), oriented)


def regress(rows: np.ndarray, oriented: bool) -> FittedWeights:
    """The weights from stacked rows (gravity, spring, discomfort), shape (n, 3).

    Each row is one null direction's components of the three gradients.
    """
    # Imported here: scipy.optimize takes about 0.6 s to import, and every
    # process that reads a motion model imports this package; only a fit
    # regresses.
    from scipy.optimize import nnls  # type: ignore[import-untyped]

    gravity = rows[:, 0]
    columns = rows[:, 1:3] if oriented else rows[:, 1:2]
    weights, residual = nnls(columns, -gravity)
    scale = float(np.linalg.norm(gravity))
    explained = 0.0 if scale == 0.0 else max(0.0, 1.0 - float(residual) / scale)
    return FittedWeights(
        mu=_bounded(weights[0]),
        omega=_bounded(weights[1]) if oriented else None,
        samples=len(rows),
        explained=round(explained, 6),
    )


def trial_rows(trial: Trial, stride: int) -> list[np.ndarray]:
    """The regression rows of one trial's kept samples, each shape (k, 3).

    Without wrist frames the task is the wrist position alone and WristYaw's
    angle is unknown: the discomfort column is 0.
    """
    arm = load_arm(trial.arm)
    chain = chain_for(arm)
    picked = np.arange(0, len(trial.times), stride)
    frames = trial.wrist_frame
    postures = joint_path_from_points(
        arm,
        trial.elbow[picked],
        trial.wrist[picked],
        None if frames is None else frames[picked],
    )
    out = []
    for k, q in zip(picked, postures, strict=True):
        palm = None if frames is None else arm.side.sign * frames[k][:, 1]
        task = WristTask.make(trial.wrist[k], palm, arm.side.sign)
        if _usable(arm, chain, q, trial.elbow[k], task):
            rows = null_space_rows(chain, q, task, MeasureParams().wrist_centre)
            if frames is None:
                rows[:, 2] = 0.0
            out.append(rows)
    return out


def null_space_rows(
    chain: Chain, q: np.ndarray, task: WristTask, centre: float
) -> np.ndarray:
    """The three gradients along the task's null space at ``q``, shape (k, 3).

    Columns: GPE [J/rad], the swivel spring per unit mu [J/rad per J/rad^2],
    the wrist discomfort per unit omega (about ``centre`` [rad]).
    """
    st = chain.state(q)
    _, cols = task.residual(st)
    jacobian = np.array(cols, dtype=float).T
    _, values, vt = np.linalg.svd(jacobian)
    rank = int(np.sum(values > RANK_TOL * values[0]))
    null = vt[rank:]
    gravity = np.array(TotalPotentialEnergy(0.0).gradient(st))
    spring = np.array(TotalPotentialEnergy(1.0).gradient(st)) - gravity
    wrist = np.zeros(5)
    wrist[WRIST_YAW] = 2.0 * (q[WRIST_YAW] - centre)
    return np.stack((null @ gravity, null @ spring, null @ wrist), axis=1)


def _usable(
    arm: ArmModel, chain: Chain, q: np.ndarray, elbow: np.ndarray, task: WristTask
) -> bool:
    """Whether ``q`` is an interior posture on the retargeted points."""
    lower, upper = arm.limits.lower, arm.limits.upper
    if np.any(q - lower < EDGE) or np.any(upper - q < EDGE):
        return False
    st = chain.state(q)
    if float(np.linalg.norm(np.array(st.p_elbow) - elbow)) > MISS:
        return False
    if task.position_error(st) > MISS:
        return False
    return task.palm_error(st) <= MISS_ROLL


def _bounded(value: float) -> float:
    """A fitted weight, 4 significant digits, within a measure's bound."""
    return min(float(f"{float(value):.4g}"), MOST)
