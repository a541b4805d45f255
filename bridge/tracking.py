"""How closely the robot followed: measured against commanded angles.

A robot begins a call late and reports its angles late. The samples' times
count from when the call left the bridge, but the robot counts the keys from
when it has received the call: a long call at a high frame rate takes
tenths of a second to carry and parse. ``angleInterpolation`` is blocking on
a real NAO as on the simulated one, its answer comes when the movement
ends, so ``bridge.playback`` knows when the robot began, at the latest:
``Samples.start_delay`` after the call left (late by the answer's trip and
up to a control cycle). And ALMotion updates the angles once per 20 ms
control cycle, so a value read between cycles is up to one cycle old.
Compared sample by sample with the command at the same wall-clock time,
even a perfect follower shows an error of about (joint speed) x (delay).
The report therefore takes out one constant delay, the same for every
joint: the shift in [0, start delay + ``MAX_LATENCY``] that minimises the
squared error of the arm's joints over the whole movement, found on a 1 ms
grid (a hand, if any, is left out of the fit and aligned with the arm). It reports
that delay, the start delay, and the error before and after the shift, so a
follower that lags (by more than ``MAX_LATENCY`` past the robot's start, or
by an error that grows with speed and does not vanish under any single
shift) still shows up.

A sample's time is the middle of its reading's request and answer, so it is
uncertain by half the round trip. On a busy machine a reading can take a
hundred milliseconds, and its angle, compared with the command at the wrong
time, would show an error the robot never made. Only samples whose round
trip is at most ``TRUSTED_ROUND_TRIP`` are compared (if fewer than half are,
the half with the shortest round trips); the report counts those left out
and says how uncertain the compared times are.
"""

from __future__ import annotations

import numpy as np

from bridge.interpolation import positions_at, trajectory_curve
from bridge.playback import Samples
from bridge.timeline_keys import is_hand
from shared.messages import ExecutedJointStates, TrackingReport, Trajectory

#: Largest delay the alignment considers past the measured start delay [s]:
#: the control cycle, the readings' network hops to a real NAO and a shared
#: machine's scheduling. (Before the call's start was measured it had to hold
#: the call's own trip too: a 1500-frame call over a 500 kB/s link began
#: 0.43 s late, and the report showed 24 degrees RMS the robot never made.)
MAX_LATENCY = 0.25
#: Step of the delay search [s].
LATENCY_STEP = 0.001
#: Longest round trip of a reading whose sample is compared [s]: its time is
#: then known within 10 ms, half a control cycle.
TRUSTED_ROUND_TRIP = 0.02


def trusted(round_trips: np.ndarray | list[float] | None, count: int) -> np.ndarray:
    """Which of ``count`` samples have a time good enough to compare, shape (count,).

    Those whose round trip [s] is at most :data:`TRUSTED_ROUND_TRIP`; if fewer
    than half are, the half with the shortest round trips. ``None`` or empty:
    exact times, all are compared.
    """
    if round_trips is None or len(round_trips) == 0:
        return np.ones(count, dtype=bool)
    trips = np.asarray(round_trips, dtype=float)
    keep = trips <= TRUSTED_ROUND_TRIP
    if 2 * int(keep.sum()) < count:
        keep = np.zeros(count, dtype=bool)
        keep[np.argsort(trips, kind="stable")[: (count + 1) // 2]] = True
    return keep


def largest_latency(samples: Samples) -> float:
    """The largest delay the alignment considers [s]: start delay + MAX_LATENCY."""
    return samples.start_delay + MAX_LATENCY


def best_latency(trajectory: Trajectory, samples: Samples) -> float:
    """The delay [s] that best aligns measured with commanded.

    It is searched in [0, :func:`largest_latency`] on a ``LATENCY_STEP`` grid;
    only the samples whose time is :func:`trusted` count, and only the arm's
    joints: a hand's open fraction is no angle to add to their radians, and
    a hand held open by what it grasps would pull the delay toward wherever
    its command passes that opening. The hand's own figures use the arm's
    delay.
    """
    keep = trusted(samples.round_trips, len(samples.times))
    times = samples.times[keep]
    if len(times) < 2:
        return 0.0
    arm = np.array([not is_hand(name) for name in trajectory.joint_names])
    measured = samples.positions.reshape(len(samples.times), -1)[keep][:, arm]
    curve = trajectory_curve(trajectory)
    count = int(np.floor(largest_latency(samples) / LATENCY_STEP + 1e-9)) + 1
    shifts = np.arange(count) * LATENCY_STEP
    costs = [float(np.sum((measured - curve(times - s)[:, arm]) ** 2)) for s in shifts]
    return float(shifts[int(np.argmin(costs))])


def executed_states(trajectory: Trajectory, samples: Samples) -> ExecutedJointStates:
    """The measured samples beside the trajectory's angles, latency taken out."""
    latency = best_latency(trajectory, samples)
    commanded = positions_at(trajectory, samples.times - latency)
    trips = [] if samples.round_trips is None else samples.round_trips.tolist()
    return ExecutedJointStates(
        arm=trajectory.arm,
        joint_names=list(trajectory.joint_names),
        times=samples.times.tolist(),
        measured=samples.positions.tolist(),
        commanded=commanded.reshape(samples.positions.shape).tolist(),
        latency=latency,
        start_delay=samples.start_delay,
        round_trips=trips,
    )


def tracking_report(
    states: ExecutedJointStates, trajectory: Trajectory | None = None
) -> TrackingReport:
    """RMS and largest error per joint [deg] of measured minus commanded.

    Only the samples whose time is :func:`trusted` are compared. A hand
    among the states' joints (its value an open fraction, not an angle) is
    reported apart, in open fraction (``hand_tracking_rms``,
    ``hand_tracking_max``); the per-joint tables hold the arm's joints.

    Args:
        states: Measured and (latency-aligned) commanded angles.
        trajectory: The commanded trajectory (the hand as a joint, if the
            states hold one); if given, the report also holds the RMS error
            without the latency alignment.
    """
    names = list(states.joint_names)
    arm = np.array([not is_hand(name) for name in names], dtype=bool)
    joints = [name for name, kept in zip(names, arm, strict=True) if kept]
    keep = trusted(states.round_trips, len(states.times))
    times = np.asarray(states.times, dtype=float)[keep]
    measured = np.asarray(states.measured).reshape(-1, len(names))[keep]
    commanded = np.asarray(states.commanded).reshape(-1, len(names))[keep]
    error = np.degrees(measured[:, arm] - commanded[:, arm])
    count = len(times)
    unaligned: dict[str, float] = {}
    if trajectory is not None and count:
        raw = np.degrees(measured - positions_at(trajectory, times))[:, arm]
        unaligned = dict(zip(joints, _rms(raw).tolist(), strict=True))
    rms = _rms(error) if count else np.zeros(len(joints))
    worst = np.max(np.abs(error), axis=0) if count else np.zeros(len(joints))
    period = float(np.mean(np.diff(times))) if count > 1 else 0.0
    trips = (
        np.asarray(states.round_trips, dtype=float)[keep] if states.round_trips else []
    )
    hand = _hand_errors(measured[:, ~arm] - commanded[:, ~arm])
    return TrackingReport(
        joint_names=joints,
        tracking_rms_deg=dict(zip(joints, rms.tolist(), strict=True)),
        tracking_max_deg=dict(zip(joints, worst.tolist(), strict=True)),
        latency=states.latency,
        start_delay=states.start_delay,
        unaligned_rms_deg=unaligned,
        samples=count,
        discarded=len(states.times) - count,
        time_uncertainty=float(np.max(trips)) / 2 if len(trips) else 0.0,
        sample_period=period,
        duration=float(states.times[-1]) if states.times else 0.0,
        hand_tracking_rms=hand[0],
        hand_tracking_max=hand[1],
    )


def _hand_errors(error: np.ndarray) -> tuple[float | None, float | None]:
    """RMS and largest of the hand's errors [-], shape (k, 0 or 1); None: no hand."""
    if error.shape[1] == 0:
        return None, None
    if len(error) == 0:
        return 0.0, 0.0
    return float(_rms(error)[0]), float(np.max(np.abs(error)))


def _rms(error: np.ndarray) -> np.ndarray:
    return np.sqrt(np.mean(error**2, axis=0))
