"""Exponential densities of the motion variables (paper Section III.A).

The rate is fitted by maximum likelihood and checked by leave-one-out
cross-validation.

    p(x) = gamma exp(-gamma x),  x >= 0.

The maximum-likelihood rate of samples x_1..x_n is gamma = n / sum(x). The
leave-one-out estimate without sample i is gamma_-i = (n - 1) / (sum(x) - x_i)
(closed form, no refits), and the cross-validated log-likelihood is the mean
of log p(x_i; gamma_-i): how well the density predicts a sample it was not
fitted on. It is defined only if every gamma_-i is, that is with at least two
nonzero samples (``MIN_NONZERO``): leaving out the only one leaves a zero sum
and an infinite rate (it read about -1e307, from a floor on that sum).
The quantiles of the fitted density cut each variable into states of equal
probability for the network (``discretize``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from shared.errors import InvalidInputError, TooFewSamplesError

#: Fewest nonzero samples for the leave-one-out rates to exist: without
#: sample i, the rest must have a nonzero sum.
MIN_NONZERO = 2


class ExponentialFit(NamedTuple):
    """A fitted exponential density.

    Attributes:
        rate: gamma, by maximum likelihood [1/unit of the variable].
        samples: How many samples it was fitted on.
        log_likelihood: Mean log-density of the samples at ``rate``.
        loo_log_likelihood: Mean leave-one-out log-density (cross-validated).
    """

    rate: float
    samples: int
    log_likelihood: float
    loo_log_likelihood: float

    @property
    def mean(self) -> float:
        """The density's mean, 1 / gamma."""
        return 1.0 / self.rate


def fit_exponential(x: np.ndarray, name: str = "x") -> ExponentialFit:
    """Maximum-likelihood rate and leave-one-out log-likelihood of samples ``x``.

    Args:
        x: Samples, shape (n,), n >= 2, finite and >= 0, at least
            ``MIN_NONZERO`` of them nonzero.
        name: The variable's name, for errors.

    Raises:
        InvalidInputError: naming ``name`` if the samples cannot be fitted;
            ``TooFewSamplesError`` if too few are (nonzero) to cross-validate.
    """
    x = np.asarray(x, dtype=float).ravel()
    if x.size < 2:
        raise TooFewSamplesError(
            f"{name}: an exponential density needs at least 2 samples, got {x.size}",
            field=name,
            found=x.size,
            needed=2,
        )
    if not np.all(np.isfinite(x)) or np.any(x < 0):
        raise InvalidInputError(f"{name}: samples must be finite and >= 0", field=name)
    total = float(x.sum())
    if total <= 0.0:
        raise InvalidInputError(f"{name}: every sample is zero", field=name)
    nonzero = int(np.count_nonzero(x))
    if nonzero < MIN_NONZERO:
        raise TooFewSamplesError(
            f"{name}: only {nonzero} of {x.size} samples is nonzero; leave-one-out "
            f"cross-validation needs at least {MIN_NONZERO}, so that the rate "
            "fitted without any one sample rests on a nonzero sum",
            field=name,
            found=nonzero,
            needed=MIN_NONZERO,
        )
    n = x.size
    rate = n / total
    return ExponentialFit(
        rate, n, math.log(rate) - 1.0, float(loo_log_densities(x).mean())
    )


def loo_log_densities(x: np.ndarray) -> np.ndarray:
    """log p(x_i; gamma_-i) for each sample, gamma_-i fitted without it, (n,).

    ``x``: samples, shape (n,), >= 0, at least ``MIN_NONZERO`` nonzero. The
    sum without sample i is sum(x) - x_i, except for the largest sample: its
    rest is summed anew, as the subtraction cancels to 0 when the others are
    tiny beside it (every other rest is at least the largest sample).
    """
    n = x.size
    rest = float(x.sum()) - x
    top = int(np.argmax(x))
    rest[top] = float(np.delete(x, top).sum())
    rates = (n - 1) / rest
    return np.log(rates) - rates * x


def log_density(x: np.ndarray, rate: float) -> np.ndarray:
    """log p(x) of the exponential density with rate ``rate``, shape of ``x``."""
    return math.log(rate) - rate * np.asarray(x, dtype=float)


def quantiles(rate: float, probabilities: np.ndarray) -> np.ndarray:
    """x such that P(X <= x) = p for the exponential density, shape of p."""
    return -np.log1p(-np.asarray(probabilities, dtype=float)) / rate
