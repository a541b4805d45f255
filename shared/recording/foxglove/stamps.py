"""When each sample of a timed message applies, as a derived message's log time.

A trajectory's samples are placed at the message's arrival plus each
sample's time from its first sample, in [ns since the epoch]; a decision's
at its arrival plus when the trajectory passes each point
(``Decision.trajectory_times``, from the trajectory's first sample), or,
without them, as a trajectory's. They are checked against MCAP's range
before any derived message is made, so a message is either derived whole
or not at all.
"""

from __future__ import annotations

from collections.abc import Sequence

from shared.recording.writer import MAX_TIME

_NS_PER_S = 1_000_000_000


def sample_stamps(
    times: Sequence[float], start: int, origin: float | None = None
) -> list[int]:
    """When each sample applies [ns since the epoch].

    Args:
        times: Sample times [s], shape (n,).
        start: When time ``origin`` applies [ns since the epoch].
        origin: The time [s] that applies at ``start``; default the first
            sample's.

    Raises:
        ValueError: if a stamp passes MCAP's range (0 to 2^64 ns), naming it.
    """
    t0 = times[0] if origin is None else origin
    stamps = [start + round((t - t0) * _NS_PER_S) for t in times]
    for i, stamp in enumerate(stamps):
        check_stamp(stamp, f"sample {i}")
    return stamps


def check_stamp(stamp: int, what: str) -> int:
    """``stamp`` [ns] if it is within MCAP's range.

    Raises:
        ValueError: naming ``what`` and the stamp.
    """
    if not 0 <= stamp <= MAX_TIME:
        raise ValueError(
            f"its times pass MCAP's range (0 to 2^64 ns): {what} falls at {stamp} ns"
        )
    return stamp
