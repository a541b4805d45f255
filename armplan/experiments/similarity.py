"""The similarity experiment (paper Section V.A, Fig. 14-15) on NAO.

For every subject and grid point of a demonstration set: the subject's mean
retargeted reach (``subject_reach``), NAO's reach from the same start to the
same goal with each method (``nao_reach``), and the elbow error

    e = mean over tau of | elbow_NAO(tau) - elbow_subject(tau) |   [m],

tau the normalised time of the reach (``normalised_time``) on an even grid.
The paper's Fig. 14 is the distribution of e per point over the subjects,
Fig. 15 its mean per point; here for ``mp`` and both baselines.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from armplan.experiments.nao_reach import PathSource, nao_reach
from armplan.experiments.normalised_time import SAMPLES, tau_grid
from armplan.experiments.subject_reach import SubjectReach, subject_reaches
from services.decide.grid_table import MIN_POINTS, sequence
from services.planner.stages import LocalStages, Stages
from shared.demos.trial import DemoSet
from shared.messages import Method
from shared.messages.measure_params import MeasureParams
from shared.robot.arm_model import load_arm

#: The methods compared, the paper's first.
METHODS = (Method.MP, Method.LEAST_NORM, Method.SINGLE)


class ReachError(NamedTuple):
    """One subject's reach to one point, planned with one method.

    Attributes:
        subject: The subject's name.
        point: Grid point 1..16.
        method: The planning method.
        elbow_error: Mean elbow distance over normalised time [m].
        wrist_error: Mean wrist distance over normalised time [m].
        primitives: The primitives that moved NAO's arm, in order (runs of
            at least ``MIN_POINTS`` path points; one label for a baseline).
        human_primitives: Primitives of the subject's most common sequence.
    """

    subject: str
    point: int
    method: Method
    elbow_error: float
    wrist_error: float
    primitives: list[str]
    human_primitives: list[str]


def run_similarity(
    demos: DemoSet,
    source: PathSource = PathSource.HUMAN,
    samples: int = SAMPLES,
    stages: Stages | None = None,
    methods: tuple[Method, ...] = METHODS,
    progress: Callable[[int, int], None] | None = None,
    measures: MeasureParams | None = None,
) -> list[ReachError]:
    """The experiment on ``demos`` (right-arm reaches on the grid).

    Args:
        demos: Demonstrations retargeted to NAO.
        source: Where NAO's wrist path comes from (``nao_reach``).
        samples: Samples of normalised time compared per reach.
        stages: The planner's stages (default: in this process, shipped model).
        methods: The methods to run.
        progress: Called with (reaches done, reaches in all) after each.
        measures: The IK measures' weights; default the shipped ones.
    """
    tau = tau_grid(samples)
    stages = stages or LocalStages()
    out = []
    reaches = subject_reaches(demos, tau)
    for done, reach in enumerate(reaches, start=1):
        arm = load_arm(_arm_of(demos, reach))
        for method in methods:
            nao = nao_reach(arm, stages, reach, method, source, tau, measures)
            out.append(
                ReachError(
                    reach.subject,
                    reach.point,
                    method,
                    mean_distance(nao.elbow, reach.elbow),
                    mean_distance(nao.wrist, reach.wrist),
                    sequence(nao.primitives, MIN_POINTS)[0],
                    _human_sequence(reach),
                )
            )
        if progress is not None:
            progress(done, len(reaches))
    return out


def _arm_of(demos: DemoSet, reach: SubjectReach) -> str:
    """The arm of the subject's trials at the point."""
    for trial in demos.trials:
        if trial.subject == reach.subject and trial.point == reach.point:
            return trial.arm.value
    return "right"


def mean_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Mean distance between two point paths [m], each shape (m, 3)."""
    return float(np.mean(np.linalg.norm(a - b, axis=1)))


def _human_sequence(reach: SubjectReach) -> list[str]:
    """The most common primitive sequence of the subject's trials (or [])."""
    if not reach.labels:
        return []
    seqs = Counter(tuple(sequence(labels)[0]) for labels in reach.labels)
    return list(seqs.most_common(1)[0][0])
