"""NAO's reach for a subject's: same start posture, same goal, a method's IK.

NAO starts in the subject's retargeted start posture (the paper: "when the
sizes of the subjects are different, the initial positions of NAO are also
different"), turned into joint angles by ``posture_from_points``. Then the
wrist either

- ``human`` path: follows the subject's mean retargeted wrist path (the
  "converted path trajectories" of Section V.A), sampled at 100 Hz over the
  subject's mean duration; the three methods then differ only in how they
  place the elbow; or
- ``planned`` path: follows the planner's own human-like wrist path from the
  start to the subject's mean end point (``services.planner.reach_path``),
  as ``armplan plan`` would.

Either way the planner's stages decide (method ``mp``) and track the path
(:class:`services.planner.stages.LocalStages`); the joint path is read at
normalised time (its points are evenly spaced in the reach's time). It is
not retimed: timing does not change the path the arm takes.
"""

from __future__ import annotations

import math
from enum import StrEnum
from typing import NamedTuple

import numpy as np

from armplan.experiments.normalised_time import at_tau_even
from armplan.experiments.subject_reach import SubjectReach
from services.planner.pipeline import track_movement
from services.planner.reach_path import reach_wrist_path
from services.planner.stages import Stages
from shared.demos.posture_from_points import joints_from_points
from shared.messages import JointPath, Method, ReachTarget, WristPath
from shared.messages.measure_params import MeasureParams
from shared.robot.arm_model import ArmModel

#: Path points per second of the human path [Hz] (the paper's 100 Hz).
RATE = 100.0


class PathSource(StrEnum):
    """Where NAO's wrist path comes from."""

    HUMAN = "human"
    PLANNED = "planned"


class NaoReach(NamedTuple):
    """NAO's reach, read at the tau grid.

    Attributes:
        elbow: Elbow positions [m], shape (m, 3).
        wrist: Wrist positions [m], shape (m, 3).
        primitives: What moved the arm at each path point, shape (n,).
        q: Joint angles [rad], shape (m, 5).
    """

    elbow: np.ndarray
    wrist: np.ndarray
    primitives: list[str]
    q: np.ndarray


def start_posture(arm: ArmModel, reach: SubjectReach) -> np.ndarray:
    """The subject's start posture on NAO [rad], shape (5,)."""
    return joints_from_points(arm, reach.elbow[0], reach.wrist[0])


def nao_reach(
    arm: ArmModel,
    stages: Stages,
    reach: SubjectReach,
    method: Method,
    source: PathSource,
    tau: np.ndarray,
    measures: MeasureParams | None = None,
    turn: PalmTurn | None = None,
) -> NaoReach:
    """NAO's reach for ``reach`` with ``method`` (see the module docstring).

    With ``turn`` NAO starts in ``turn.start`` and turns its palm to
    ``turn.palm`` on the way; without, it starts in ``start_posture`` and
    has no palm to turn.
    """
    q0 = start_posture(arm, reach) if turn is None else turn.start
    path = wrist_path(arm, reach, q0, source, tau, None if turn is None else turn.palm)
    joint_path = track(stages, path, q0, method, measures)
    q = np.array(joint_path.positions)
    elbow = np.array([arm.fk(posture).elbow for posture in q])
    return NaoReach(
        at_tau_even(elbow, tau),
        at_tau_even(np.array(joint_path.wrist), tau),
        list(joint_path.primitives),
        at_tau_even(q, tau),
    )


class PalmTurn(NamedTuple):
    """A reach's start posture and the palm to turn to on the way.

    Attributes:
        start: Start posture [rad], shape (5,).
        palm: Palm direction to reach (unit), shape (3,).
    """

    start: np.ndarray
    palm: np.ndarray


def wrist_path(
    arm: ArmModel,
    reach: SubjectReach,
    q0: np.ndarray,
    source: PathSource,
    tau: np.ndarray,
    palm: np.ndarray | None = None,
) -> WristPath:
    """NAO's wrist path from the posture ``q0`` [rad] (see the module docstring).

    ``palm``: the palm direction to turn to on the way (unit, shape (3,)), or
    ``None``.
    """
    start = arm.fk(q0).wrist
    facing = None if palm is None else tuple(float(v) for v in palm)
    if source is PathSource.PLANNED:
        end = tuple(float(v) for v in reach.wrist[-1])
        return reach_wrist_path(arm, q0, ReachTarget(position=end, palm=facing))
    n = max(2, math.ceil(reach.duration * RATE) + 1)
    times = np.linspace(0.0, reach.duration, n)
    positions = np.stack(
        [np.interp(times / reach.duration, tau, reach.wrist[:, i]) for i in range(3)],
        axis=1,
    )
    positions[0] = start  # q0 may sit a hair off the human start (joint limits)
    return WristPath(
        arm=arm.side,
        times=times.tolist(),
        positions=[tuple(p) for p in positions.tolist()],
        palm=facing,
    )


def track(
    stages: Stages,
    path: WristPath,
    q0: np.ndarray,
    method: Method,
    measures: MeasureParams | None = None,
) -> JointPath:
    """Decide (method ``mp``) and track ``path`` from ``q0``, as the planner does."""
    return track_movement(stages, path, q0, method, measures or MeasureParams())[0]
