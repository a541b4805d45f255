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
from shared.errors import InvalidInputError


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
    ],
)
def test_unfittable_samples(x: list[float], message: str) -> None:
    """Samples an exponential cannot fit raise an error naming the variable."""
    with pytest.raises(InvalidInputError, match=f"S_R: .*{message}"):
        fit_exponential(np.array(x), "S_R")
