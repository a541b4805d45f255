"""Which reaches the similarity experiment compares: grid points averaged per
subject and arm, reaches off the grid alone, unlabelled ones counted apart."""

from __future__ import annotations

import numpy as np
import pytest

from armplan.experiments.similarity import ReachError, run_similarity
from armplan.experiments.similarity_summary import summary
from armplan.experiments.subject_reach import subject_reaches
from shared.demos import synthesize
from shared.demos.trial import DemoSet, Trial
from shared.messages import Method
from shared.robot import Side

#: Samples of normalised time per reach: few, for speed.
SAMPLES = 11
#: NAO's mirror of a right-arm point onto the left: y flips.
FLIP = np.diag([1.0, -1.0, 1.0])


@pytest.fixture(scope="module")
def demos() -> DemoSet:
    """One subject, two trials at each of two points; labelled."""
    return synthesize(5, subjects=1, trials=2, points=(3, 10))


def errors(rows: list[ReachError]) -> dict[tuple[str, int, str, int], float]:
    return {
        (*r.reach[:3], r.reach[3]): r.elbow_error for r in rows if r.method is Method.MP
    }


def off_grid(trial: Trial) -> Trial:
    return trial._replace(point=0)


def left(trial: Trial) -> Trial:
    """The trial done by the left arm (wrist frames left out: no palm here)."""
    return trial._replace(
        arm=Side.LEFT,
        shoulder=trial.shoulder @ FLIP,
        elbow=trial.elbow @ FLIP,
        wrist=trial.wrist @ FLIP,
        target=trial.target @ FLIP,
        wrist_frame=None,
    )


def test_reaches_off_the_grid_are_compared_each_alone(demos: DemoSet) -> None:
    """Imported reaches have no grid point: they were refused ("no trial on
    the 16-point grid"). Each is now a reach alone, and its error is the one
    the same trial gets as the only trial at a grid point."""
    tau = np.linspace(0.0, 1.0, SAMPLES)
    firsts = [t for t in demos.trials if t.trial % 2 == 0]
    alone = DemoSet(demos.subjects, firsts)
    moved = DemoSet(demos.subjects, [off_grid(t) for t in firsts])
    assert [r.trials for r in subject_reaches(moved, tau)] == [1] * len(firsts)
    on, off = (
        run_similarity(alone, samples=SAMPLES),
        run_similarity(moved, samples=SAMPLES),
    )
    on_errors = sorted(r.elbow_error for r in on if r.method is Method.MP)
    off_errors = sorted(r.elbow_error for r in off if r.method is Method.MP)
    assert off_errors == pytest.approx(on_errors, abs=1e-12)
    assert {r.trial for r in off} == {t.trial for t in firsts}
    numbers = summary(off, {})
    assert list(numbers["mp"]["per_point_mean_elbow_error_m"]) == ["off-grid"]
    assert numbers["mp"]["reaches"] == len(firsts)


def test_the_two_arms_are_never_averaged_together(demos: DemoSet) -> None:
    """Left and right trials of one subject at one point were averaged into
    one reach (a wrist near y = 0), planned from the right shoulder. Now each
    arm's reach is planned with its own arm: the mirror gives the same errors."""
    both = DemoSet(demos.subjects, [*demos.trials, *(left(t) for t in demos.trials)])
    rows = run_similarity(both, samples=SAMPLES)
    found = errors(rows)
    right = {k: v for k, v in found.items() if k[2] == "right"}
    assert len(right) == 2 and len(found) == 4
    for (subject, point, _, trial), error in right.items():
        assert found[(subject, point, "left", trial)] == pytest.approx(error, abs=1e-9)


def test_unlabelled_reaches_are_counted_as_unknown(demos: DemoSet) -> None:
    """Recorded reaches carry no primitive labels: they went into a group of
    '0 primitives', which no reach has; now into 'unknown'."""
    bare = DemoSet(demos.subjects, [t._replace(labels=None) for t in demos.trials])
    numbers = summary(run_similarity(bare, samples=SAMPLES), {})
    assert list(numbers["by_human_primitive_count"]) == ["unknown"]
    assert numbers["by_human_primitive_count"]["unknown"]["reaches"] == 2
    labelled = summary(run_similarity(demos, samples=SAMPLES), {})
    assert "unknown" not in labelled["by_human_primitive_count"]
