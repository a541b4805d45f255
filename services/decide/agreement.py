"""How often the decision agrees with the demonstrations' labels.

The decision runs along each recorded trial, sample by sample, on the
trial's own (retargeted) states: the variables of the sample with the
trial's end as the goal, and the decision made at the sample before (never
the label) as the primitive before. Its winner is compared with the label.
Used on subjects left out of the fit, this is the held-out agreement.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from services.decide.decider import CANDIDATES, Decider
from services.fit.demo_variables import trial_variables
from services.fit.labelling import infer_labels
from services.fit.model import MotionModel
from shared.demos.retarget import nao_arm_size
from shared.demos.trial import DemoSet, Trial


class Agreement(NamedTuple):
    """Decisions against labels.

    Attributes:
        samples: Samples compared.
        agreed: Samples where the decision equals the label.
        confusion: Counts, rows the labels, columns the decisions, both in
            ``CANDIDATES`` order, shape (8, 8).
    """

    samples: int
    agreed: int
    confusion: np.ndarray

    @property
    def fraction(self) -> float:
        """Share of samples where the decision equals the label."""
        return self.agreed / self.samples if self.samples else 0.0

    def rows(self) -> list[tuple[str, list[int]]]:
        """(label, counts per decided primitive) for the labels that occur."""
        return [
            (name, [int(c) for c in self.confusion[i]])
            for i, name in enumerate(CANDIDATES)
            if self.confusion[i].sum() > 0
        ]


def agreement(model: MotionModel, demos: DemoSet) -> Agreement:
    """Decide along every trial of ``demos`` and compare with their labels.

    Trials without labels are labelled from their motion
    (``services.fit.labelling``).
    """
    base = Decider(model)
    confusion = np.zeros((len(CANDIDATES), len(CANDIDATES)), dtype=int)
    for trial in demos.trials:
        decided = decide_trial(base, trial)
        labels = trial.labels if trial.labels is not None else infer_labels(trial)
        for label, choice in zip(labels, decided, strict=True):
            confusion[CANDIDATES.index(label), choice] += 1
    return Agreement(int(confusion.sum()), int(np.trace(confusion)), confusion)


def decide_trial(decider: Decider, trial: Trial) -> list[int]:
    """The decided primitive (index into ``CANDIDATES``) at each sample."""
    size = nao_arm_size(trial.arm)
    values = trial_variables(trial, size.upper_arm, size.forearm).tolist()
    step = float(np.median(np.diff(trial.times))) if len(trial.times) > 1 else None
    if step is not None and abs(step - decider.step) > 1e-9:
        decider = decider.with_step(step)
    oriented = trial.wrist_frame is not None
    out, previous = [], None
    for row in values:
        choice = decider.decide(tuple(row), oriented, previous)
        out.append(choice.candidate)
        previous = choice.state
    return out
