"""Normalised time: how a human's and NAO's movements are put side by side.

A reach of duration T is read at normalised time tau = (t - t_0) / T in
[0, 1], so the start matches the start and the end the end, whatever the
two movements' durations. Both are sampled at the same ``samples`` values of
tau, evenly spaced, by linear interpolation between their own samples.
"""

from __future__ import annotations

import numpy as np

from shared.errors import InvalidInputError

#: Values of tau at which movements are compared, by default.
SAMPLES = 101
#: Fewest values of tau: a tenth of the movement apart. Fewer read the
#: subject's wrist path as a few chords, not the path: with 2 a reach from
#: the hanging arm became one straight line through NAO's shoulder, refused
#: as a reach NAO cannot make, blaming the demonstrations.
FEWEST_SAMPLES = 11
#: Most values of tau: a hundredth of a percent of the movement apart.
MOST_SAMPLES = 10_001


def tau_grid(samples: int = SAMPLES) -> np.ndarray:
    """``samples`` evenly spaced values of tau from 0 to 1, shape (samples,).

    Raises:
        InvalidInputError: if ``samples`` is not within
            ``FEWEST_SAMPLES``..``MOST_SAMPLES``.
    """
    if not FEWEST_SAMPLES <= samples <= MOST_SAMPLES:
        raise InvalidInputError(
            f"need {FEWEST_SAMPLES} to {MOST_SAMPLES} samples of normalised time, "
            f"got {samples}",
            field="samples",
        )
    return np.linspace(0.0, 1.0, samples)


def at_tau(times: np.ndarray, values: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """``values`` at normalised times ``tau``, shape (len(tau), d).

    Args:
        times: Sample times [s], shape (n,), increasing, n >= 2.
        values: Samples, shape (n, d).
        tau: Normalised times in [0, 1], shape (m,).

    Raises:
        InvalidInputError: if the times do not span a positive duration or do
            not match the values.
    """
    times = np.asarray(times, dtype=float)
    values = np.asarray(values, dtype=float)
    if len(times) != len(values) or len(times) < 2 or times[-1] <= times[0]:
        raise InvalidInputError(
            f"a movement needs >= 2 samples over a positive duration, got "
            f"{len(times)} times and {len(values)} samples",
            field="times",
        )
    own = (times - times[0]) / (times[-1] - times[0])
    columns = [np.interp(tau, own, values[:, i]) for i in range(values.shape[1])]
    return np.stack(columns, axis=1)


def at_tau_even(values: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """``values`` sampled evenly in time, at normalised times ``tau``.

    Args:
        values: Samples evenly spaced in time, shape (n, d), n >= 2.
        tau: Normalised times in [0, 1], shape (m,).
    """
    return at_tau(np.arange(len(values), dtype=float), values, tau)
