"""Exponential densities: the MLE recovers known rates; LOO CV in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from services.fit.discretize import bin_edges, bin_index, bin_indices
from services.fit.exponential import (
    fit_exponential,
    log_density,
    loo_log_densities,
    quantiles,
)
from shared.errors import InvalidInputError, TooFewSamplesError


@pytest.mark.parametrize("rate", [0.5, 3.2, 8.0, 40.0])
def test_known_rates_are_recovered(rate: float) -> None:
    """On samples from Exp(rate) the fitted rate is within 4 standard errors."""
    rng = np.random.default_rng(int(rate * 10))
    n = 20_000
    fit = fit_exponential(rng.exponential(1.0 / rate, size=n))
    assert abs(fit.rate - rate) < 4.0 * rate / math.sqrt(n)
    assert fit.samples == n
    assert fit.log_likelihood == pytest.approx(math.log(fit.rate) - 1.0)


def test_rate_is_the_maximum_of_the_likelihood() -> None:
    """Nudging the rate either way lowers the log-likelihood."""
    x = np.random.default_rng(1).exponential(0.3, size=500)
    fit = fit_exponential(x)
    best = log_density(x, fit.rate).mean()
    for factor in (0.98, 1.02):
        assert log_density(x, fit.rate * factor).mean() < best
    assert best == pytest.approx(fit.log_likelihood)


def test_leave_one_out_closed_form_equals_refitting() -> None:
    """The closed-form LOO log-densities equal fitting n times without each sample."""
    x = np.random.default_rng(2).exponential(0.7, size=40)
    brute = []
    for i in range(x.size):
        rest = np.delete(x, i)
        brute.append(log_density(x[i], fit_exponential(rest).rate))
    np.testing.assert_allclose(loo_log_densities(x), brute, rtol=1e-12)
    fit = fit_exponential(x)
    assert fit.loo_log_likelihood == pytest.approx(np.mean(brute))
    assert fit.loo_log_likelihood < fit.log_likelihood


def test_leave_one_out_of_a_dominant_sample_equals_refitting() -> None:
    """Beside a sample of 1, others of 1e-20 vanish from the sum: the LOO
    rate without it must come from those others (2 / 3e-20), as refitting
    gives, not from a floor on a cancelled sum (it gave -9e307)."""
    x = np.array([1.0, 1e-20, 2e-20])
    brute = [
        float(log_density(x[i], (x.size - 1) / np.delete(x, i).sum()))
        for i in range(x.size)
    ]
    np.testing.assert_allclose(loo_log_densities(x), brute, rtol=1e-12)
    assert loo_log_densities(x)[0] == pytest.approx(math.log(2 / 3e-20) - 2 / 3e-20)


def test_bins_have_equal_probability() -> None:
    """The edges are the density's quantiles k/K: each bin holds 1/K of samples."""
    rate, bins = 2.5, 10
    edges = bin_edges(rate, bins)
    np.testing.assert_allclose(1.0 - np.exp(-rate * edges), np.arange(1, bins) / bins)
    x = np.random.default_rng(3).exponential(1.0 / rate, size=100_000)
    counts = np.bincount(bin_indices(x, edges), minlength=bins) / x.size
    np.testing.assert_allclose(counts, 1.0 / bins, atol=0.005)
    assert [bin_index(float(v), edges.tolist()) for v in x[:50]] == list(
        bin_indices(x[:50], edges)
    )
    np.testing.assert_allclose(quantiles(rate, np.array([0.5])), math.log(2) / rate)


@pytest.mark.parametrize(
    ("x", "message"),
    [
        ([1.0], "at least 2"),
        ([0.0, 0.0, 0.0], "every sample is zero"),
        ([0.1, -0.2], ">= 0"),
        ([0.1, math.nan], "finite"),
        ([0.0, 0.7, 0.0], "only 1 of 3 samples is nonzero"),
    ],
)
def test_unfittable_samples(x: list[float], message: str) -> None:
    """Samples an exponential cannot fit raise an error naming the variable."""
    with pytest.raises(InvalidInputError, match=f"S_R: .*{message}"):
        fit_exponential(np.array(x), "S_R")


def test_one_nonzero_sample_is_too_few_to_cross_validate() -> None:
    """Two samples, one at the goal (0): the LOO rate without the other is
    infinite, so the fit is refused naming how many are needed (its LOO
    log-likelihood read -9e306, from a floor on the zero sum)."""
    with pytest.raises(TooFewSamplesError) as info:
        fit_exponential(np.array([0.0, 0.4]), "W_P")
    assert info.value.message == (
        "W_P: only 1 of 2 samples is nonzero; leave-one-out cross-validation "
        "needs at least 2, so that the rate fitted without any one sample rests "
        "on a nonzero sum"
    )
    assert (info.value.found, info.value.needed, info.value.field) == (1, 2, "W_P")
