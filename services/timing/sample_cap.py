"""The most samples a trajectory may have: the bus and the robot bridge's cap."""

from __future__ import annotations

from shared.bus.config import DEFAULT_MAX_PAYLOAD
from shared.errors import InvalidInputError
from shared.messages import TimingRequest, Trajectory
from shared.messages.target import MAX_TRAJECTORY_SAMPLES

#: Samples below which a trajectory's JSON is surely under the bus's 16 MiB
#: (a sample of a moving arm takes about 340 bytes, at most about 400):
#: above it, :func:`check_payload` measures it.
SURELY_SMALL = 40_000


def check_samples(samples: float, rate: float, field: str = "rate") -> None:
    """Refuse a trajectory of more than ``MAX_TRAJECTORY_SAMPLES`` samples.

    Args:
        samples: Its sample count (or a lower bound of it, before timing).
        rate: Its sample rate [Hz].
        field: The request's field the error names: the one that made it
            too long, if one did alone, else the rate.

    Raises:
        InvalidInputError: naming the count, the duration and the cap.
    """
    if samples > MAX_TRAJECTORY_SAMPLES:
        raise InvalidInputError(
            f"the trajectory would have {samples:.0f} samples ({samples / rate:g} s "
            f"at {rate:g} Hz), more than {MAX_TRAJECTORY_SAMPLES}, the most the bus "
            "and the robot bridge take: lower the rate or split the task",
            field=field,
            samples=float(samples),
            limit=MAX_TRAJECTORY_SAMPLES,
        )


def check_asked(request: TimingRequest) -> None:
    """Refuse a request whose asked durations and dwells alone pass the cap.

    Checked before any timing, so that an oversized request costs nothing:
    the trajectory lasts at least the sum of the wanted durations and dwells.
    A trajectory of the longest duration (``MAX_DURATION``, 600 s) at 100 Hz
    has 60 001 samples, both ends included: it passes.

    Raises:
        InvalidInputError: as :func:`check_samples`, naming the one duration
            or dwell asked (``segments.0.duration``) if only one was.
    """
    asked = [
        (f"segments.{i}.{name}", value)
        for i, s in enumerate(request.segments)
        for name, value in (("duration", s.duration or 0.0), ("dwell", s.dwell))
        if value > 0.0
    ]
    total = sum(value for _, value in asked)
    field = asked[0][0] if len(asked) == 1 else "rate"
    check_samples(total * request.rate + 1.0, request.rate, field)


#: What to do about a planned trajectory too large to send.
LOWER_RATE = "lower the rate or split the task"
#: What to do about one at a wrist path's own times (it has no rate to lower).
FEWER_SAMPLES = (
    "give the wrist path fewer samples (resample it at a lower rate) or split it"
)


def check_payload(
    trajectory: Trajectory, most: int = DEFAULT_MAX_PAYLOAD, advice: str = LOWER_RATE
) -> None:
    """Refuse a trajectory whose JSON is over ``most`` bytes (the bus's limit).

    Under ``MAX_TRAJECTORY_SAMPLES`` a trajectory of a moving arm can still
    be too large to send to the robot bridge (58 197 samples made 19.9 MB):
    it planned, and the bridge then refused it as ``payload_too_large``.

    Args:
        trajectory: The trajectory.
        most: The largest JSON [bytes].
        advice: What the message says to do.

    Raises:
        InvalidInputError: naming its size, the limit and ``advice``.
    """
    if len(trajectory.times) <= SURELY_SMALL:
        return
    size = len(trajectory.to_json().encode())
    if size > most:
        raise InvalidInputError(
            f"the trajectory's {len(trajectory.times)} samples make "
            f"{size / 1e6:.1f} MB of JSON, more than the {most / 2**20:g} MiB a "
            f"message to the robot bridge may carry: {advice}",
            field="rate",
            size=size,
            limit=most,
        )
