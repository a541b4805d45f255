"""How closely the robot followed: measured against commanded angles.

A robot reports its angles late: ALMotion updates them once per 20 ms
control cycle, so a value read between cycles is up to one cycle old, and the
request travels over the network besides. Compared sample by sample with the
command at the same wall-clock time, even a perfect follower shows an error
of about (joint speed) x (delay). The report therefore takes out one
constant delay, the same for every joint: the shift in [0, ``MAX_LATENCY``]
that minimises the squared error over the whole movement, found on a 1 ms
grid. It reports that delay and the error before and after the shift, so a
follower that lags (an error that grows with speed and does not vanish under
any single shift) still shows up.
"""

from __future__ import annotations

import numpy as np

from bridge.interpolation import positions_at
from bridge.playback import Samples
from shared.messages import ExecutedJointStates, TrackingReport, Trajectory

#: Largest delay the alignment considers [s]: a network hop to a real NAO and
#: a shared machine's scheduling included (on a loaded 2-CPU machine the call
#: reached the simulated NAO more than 60 ms after it left the bridge).
MAX_LATENCY = 0.25
#: Step of the delay search [s].
LATENCY_STEP = 0.001


def best_latency(trajectory: Trajectory, samples: Samples) -> float:
    """The delay [s] in [0, MAX_LATENCY] that best aligns measured with commanded."""
    if len(samples.times) < 2:
        return 0.0
    measured = samples.positions.reshape(len(samples.times), -1)
    shifts = np.arange(0.0, MAX_LATENCY + LATENCY_STEP / 2, LATENCY_STEP)
    costs = [
        float(np.sum((measured - positions_at(trajectory, samples.times - s)) ** 2))
        for s in shifts
    ]
    return float(shifts[int(np.argmin(costs))])


def executed_states(trajectory: Trajectory, samples: Samples) -> ExecutedJointStates:
    """The measured samples beside the trajectory's angles, latency taken out."""
    latency = best_latency(trajectory, samples)
    commanded = positions_at(trajectory, samples.times - latency)
    return ExecutedJointStates(
        arm=trajectory.arm,
        joint_names=list(trajectory.joint_names),
        times=samples.times.tolist(),
        measured=samples.positions.tolist(),
        commanded=commanded.reshape(samples.positions.shape).tolist(),
        latency=latency,
    )


def tracking_report(
    states: ExecutedJointStates, trajectory: Trajectory | None = None
) -> TrackingReport:
    """RMS and largest error per joint [deg] of measured minus commanded.

    Args:
        states: Measured and (latency-aligned) commanded angles.
        trajectory: The commanded trajectory; if given, the report also holds
            the RMS error without the latency alignment.
    """
    names = list(states.joint_names)
    measured = np.asarray(states.measured).reshape(-1, len(names))
    error = np.degrees(measured - np.asarray(states.commanded).reshape(-1, len(names)))
    count = len(states.times)
    unaligned: dict[str, float] = {}
    if trajectory is not None and count:
        raw = np.degrees(measured - positions_at(trajectory, states.times))
        unaligned = dict(zip(names, _rms(raw).tolist(), strict=True))
    rms = _rms(error) if count else np.zeros(len(names))
    worst = np.max(np.abs(error), axis=0) if count else np.zeros(len(names))
    period = float(np.mean(np.diff(states.times))) if count > 1 else 0.0
    return TrackingReport(
        joint_names=names,
        tracking_rms_deg=dict(zip(names, rms.tolist(), strict=True)),
        tracking_max_deg=dict(zip(names, worst.tolist(), strict=True)),
        latency=states.latency,
        unaligned_rms_deg=unaligned,
        samples=count,
        sample_period=period,
        duration=float(states.times[-1]) if count else 0.0,
    )


def _rms(error: np.ndarray) -> np.ndarray:
    return np.sqrt(np.mean(error**2, axis=0))
