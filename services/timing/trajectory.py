"""The result of timing: a sampled joint trajectory and where it is on the path."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class TimedTrajectory(NamedTuple):
    """A joint trajectory sampled at a fixed rate (or at given times).

    Attributes:
        times: Sample times from the start [s], shape (m,).
        positions: Joint angles [rad], shape (m, n).
        velocities: Joint speeds [rad/s], shape (m, n).
        accelerations: Joint accelerations [rad/s^2], shape (m, n).
        jerks: Joint jerks [rad/s^3], shape (m, n).
        path_index: Where each sample is on the input path, shape (m,): 12.25
            is a quarter of the way from input point 12 to point 13 (in the
            path parameter), so labels and wrist points carry over with
            ``floor``/``round``; whole numbers at the input's stops.
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray
    jerks: np.ndarray
    path_index: np.ndarray

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return float(self.times[-1] - self.times[0])

    def shifted(self, dt: float, di: float) -> TimedTrajectory:
        """The same samples ``dt`` [s] later and ``di`` path points further."""
        return self._replace(times=self.times + dt, path_index=self.path_index + di)


def concatenate(parts: list[TimedTrajectory]) -> TimedTrajectory:
    """Parts joined in order; each part's first sample replaces the previous last.

    The parts must already be shifted to their times and path indices.
    """
    first, rest = parts[0], parts[1:]
    fields = [[np.asarray(f)] for f in first]
    for part in rest:
        for out, f in zip(fields, part, strict=True):
            out[-1] = out[-1][:-1]
            out.append(np.asarray(f))
    return TimedTrajectory(*(np.concatenate(f) for f in fields))


def hold(
    position: np.ndarray, start: float, duration: float, period: float, index: float
) -> TimedTrajectory:
    """Rest at ``position`` (n,) from ``start`` for ``duration`` [s], sampled.

    Samples at ``start``, ``start + period``, ... ``start + duration``, where
    ``duration`` is a whole number of periods.
    """
    count = round(duration / period) + 1
    times = start + np.arange(count) * period
    still = np.zeros((count, len(position)))
    return TimedTrajectory(
        times,
        np.tile(position, (count, 1)),
        still,
        still.copy(),
        still.copy(),
        np.full(count, float(index)),
    )


__all__ = ["TimedTrajectory", "concatenate", "hold"]
