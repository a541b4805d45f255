"""The most samples a trajectory may have: the bus and the robot bridge's cap."""

from __future__ import annotations

from shared.errors import InvalidInputError
from shared.messages import TimingRequest
from shared.messages.target import MAX_TRAJECTORY_SAMPLES


def check_samples(samples: float, rate: float) -> None:
    """Refuse a trajectory of more than ``MAX_TRAJECTORY_SAMPLES`` samples.

    Args:
        samples: Its sample count (or a lower bound of it, before timing).
        rate: Its sample rate [Hz].

    Raises:
        InvalidInputError: naming the count, the duration and the cap.
    """
    if samples > MAX_TRAJECTORY_SAMPLES:
        raise InvalidInputError(
            f"the trajectory would have {samples:.0f} samples ({samples / rate:g} s "
            f"at {rate:g} Hz), more than {MAX_TRAJECTORY_SAMPLES}, the most the bus "
            "and the robot bridge take: lower the rate or split the task",
            field="rate",
            samples=float(samples),
            limit=MAX_TRAJECTORY_SAMPLES,
        )


def check_asked(request: TimingRequest) -> None:
    """Refuse a request whose asked durations and dwells alone pass the cap.

    Checked before any timing, so that an oversized request costs nothing:
    the trajectory lasts at least the sum of the wanted durations and dwells.

    Raises:
        InvalidInputError: as :func:`check_samples`.
    """
    asked = sum((s.duration or 0.0) + s.dwell for s in request.segments)
    check_samples(asked * request.rate + 1.0, request.rate)
