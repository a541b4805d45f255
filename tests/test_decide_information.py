"""Transient information (eq. 5-8) and the decision's g: identities and agreement."""

from __future__ import annotations

import bisect
import math

import numpy as np
import pytest

from services.decide.accumulate import ami_terms
from services.decide.decider import CANDIDATES, Decider
from services.decide.information import ami_parallel, ami_serial, tcmi, tmi
from services.fit import MotionModel, fit_model
from shared.demos import synthesize


def _entropy(p: np.ndarray) -> float:
    p = p[p > 0]
    return float(-(p * np.log(p)).sum())


def test_tmi_sums_to_the_mutual_information(rng: np.random.Generator) -> None:
    """Summed over every state, eq. 5 is I(X;Y) = H(X) + H(Y) - H(X,Y)."""
    joint = rng.random((4, 5))
    joint /= joint.sum()
    px, py = joint.sum(1), joint.sum(0)
    total = tmi(joint, px[:, None], py[None, :]).sum()
    assert total == pytest.approx(_entropy(px) + _entropy(py) - _entropy(joint))
    independent = np.outer(px, py)
    np.testing.assert_allclose(
        tmi(independent, px[:, None], py[None, :]), 0.0, atol=1e-15
    )


def test_tcmi_sums_to_the_conditional_mutual_information(
    rng: np.random.Generator,
) -> None:
    """Summed, eq. 6 is I(X;Z|Y) = H(X,Y) + H(Y,Z) - H(Y) - H(X,Y,Z)."""
    joint = rng.random((3, 4, 5))
    joint /= joint.sum()
    pxy, pyz, py = joint.sum(2), joint.sum(0), joint.sum((0, 2))
    total = tcmi(joint, pxy[:, :, None], pyz[None], py[None, :, None]).sum()
    expected = _entropy(pxy) + _entropy(pyz) - _entropy(py) - _entropy(joint)
    assert total == pytest.approx(expected)
    assert total >= 0.0


def test_zero_probability_gives_a_zero_term() -> None:
    """An impossible state adds nothing (0 log 0 = 0)."""
    assert tmi(np.array(0.0), np.array(0.2), np.array(0.3)) == 0.0
    assert tcmi(np.array(0.0), np.array(0.1), np.array(0.1), np.array(0.2)) == 0.0


def test_ami_forms_accumulate() -> None:
    """Serial and parallel AMI add their terms (eq. 7, 8)."""
    assert ami_serial([0.1, 0.2, -0.05]) == pytest.approx(0.25)
    assert ami_parallel([0.3, 0.4]) == pytest.approx(0.7)


@pytest.fixture(scope="module")
def model() -> MotionModel:
    return fit_model(synthesize(9, subjects=3, trials=1), bins=10)


def test_decider_g_is_the_sum_of_the_ami_terms(
    model: MotionModel, rng: np.random.Generator
) -> None:
    """Fast g = serial sum of the TMI/TCMI terms = P(m,z) log P(m,z)/(P(m)P(z))."""
    decider = Decider(model)
    tables = model.conditionals()
    for _ in range(50):
        values = tuple(float(rng.exponential(1.0 / v.rate)) for v in model.variables)
        s, ep, er, wp, wr = decider.states(values)
        previous = int(rng.integers(len(model.primitives)))
        prior = np.exp(np.array(decider.log_next[previous]))
        terms = ami_terms(
            prior,
            tables.shoulder[:, s],
            tables.elbow[:, s, ep, er],
            tables.wrist[:, er, wp, wr],
        )
        choice = decider.decide(values, True, previous)
        known = [choice.g[CANDIDATES.index(p)] for p in model.primitives]
        np.testing.assert_allclose(known, terms.g, rtol=1e-9, atol=1e-300)
        joint = prior * tables.shoulder[:, s] * tables.elbow[:, s, ep, er]
        joint = joint * tables.wrist[:, er, wp, wr]
        direct = joint * np.log(joint / (prior * joint.sum()))
        np.testing.assert_allclose(terms.g, direct, rtol=1e-9, atol=1e-300)


def test_the_largest_g_wins_and_unknown_primitives_stay_out(
    model: MotionModel, rng: np.random.Generator
) -> None:
    """Eq. 10: the winner has the largest g; primitives never shown have g = 0."""
    decider = Decider(model)
    unknown = [i for i, name in enumerate(CANDIDATES) if name not in model.primitives]
    for _ in range(50):
        values = tuple(float(rng.exponential(1.0 / v.rate)) for v in model.variables)
        choice = decider.decide(values, bool(rng.integers(2)), None)
        assert choice.g[choice.candidate] == max(choice.g)
        assert all(choice.g[i] == 0.0 for i in unknown)
        assert CANDIDATES[choice.candidate] in model.primitives
        assert not any(math.isnan(v) for v in choice.g)


def test_states_bisect_like_the_standard_library(
    model: MotionModel, rng: np.random.Generator
) -> None:
    """A variable's state is bisect.bisect_right over its bin edges, edges included."""
    decider = Decider(model)
    for k, edges in enumerate(decider.edges):
        values = [*edges, *rng.uniform(-1.0, 2.0 * max(edges), 200).tolist()]
        for value in values:
            probe = [0.0] * 5
            probe[k] = value
            assert decider.states(tuple(probe))[k] == bisect.bisect_right(edges, value)
