"""On subjects left out of the fit the decision agrees with the labels (>= 90 %)."""

from __future__ import annotations

import numpy as np
import pytest

from services.decide.agreement import Agreement, agreement, decide_trial
from services.decide.decider import CANDIDATES, Decider
from services.fit import fit_model
from shared.demos import DemoSet, synthesize

HELD_OUT = {"S13", "S14", "S15", "S16"}


@pytest.fixture(scope="module")
def demos() -> DemoSet:
    return synthesize(0)  # the paper's protocol: 16 subjects x 16 points x 5


@pytest.fixture(scope="module")
def held_out(demos: DemoSet) -> Agreement:
    train = demos.only(set(demos.subjects) - HELD_OUT)
    return agreement(fit_model(train), demos.only(HELD_OUT))


def test_held_out_agreement_is_at_least_90_percent(
    held_out: Agreement, demos: DemoSet
) -> None:
    """Sample by sample, on four unseen subjects, >= 90 % equal the labels."""
    print(
        f"\nheld-out agreement {100 * held_out.fraction:.2f} % "
        f"({held_out.agreed} of {held_out.samples} samples)"
    )
    used = [i for i in range(len(CANDIDATES)) if held_out.confusion[:, i].any()]
    print("confusion (rows labels, columns decisions):", [CANDIDATES[i] for i in used])
    for label, counts in held_out.rows():
        print(f"  {label:>14}", [counts[i] for i in used])
    assert held_out.samples == demos.only(HELD_OUT).samples
    assert held_out.fraction >= 0.90


def test_every_primitive_class_is_mostly_right(held_out: Agreement) -> None:
    """Each labelled primitive is decided correctly on most of its samples."""
    for i, name in enumerate(CANDIDATES):
        row = held_out.confusion[i]
        if row.sum():
            assert row[i] / row.sum() > 0.75, name


def test_decisions_use_the_decision_before_not_the_label(demos: DemoSet) -> None:
    """Deciding a trial twice gives the same sequence; it starts at the start table."""
    model = fit_model(demos.only({"S01", "S02"}), bins=10)
    decider = Decider(model)
    trial = demos.trials[-1]
    first, again = decide_trial(decider, trial), decide_trial(decider, trial)
    assert first == again
    assert len(first) == len(trial.times)
    assert np.isin(first, [CANDIDATES.index(p) for p in model.primitives]).all()
