"""Primitive labels for recorded reaches, from which joints move.

Synthetic demonstrations come labelled by their generator; recorded ones
(C3D, CSV) do not. This labels them the way a person reading the joint
curves would: a joint moves while its angular speed exceeds ``ACTIVE`` of
its peak in the trial (and ``FLOOR``, so that a joint that hardly moves is
never active). The shoulder's speed is the rotation rate of the upper-arm
frame (swing and humeral rotation), the elbow's the rate of its flexion,
the forearm's the rate of its roll; the labels follow
``shared.demos.labels``. Marker noise is removed first with a zero-lag
low-pass filter (2nd-order Butterworth at ``CUTOFF``, run forwards and
backwards), the usual treatment of arm markers (Winter 2009, ch. 3).
"""

from __future__ import annotations

import numpy as np

from shared.demos.labels import labels_from_motion
from shared.demos.rotations import unit
from shared.demos.trial import Trial
from shared.demos.wrist_roll import forearm_roll

#: A joint counts as moving above this fraction of its peak speed.
ACTIVE = 0.15
#: ... and above this speed [rad/s].
FLOOR = 0.3
#: Cut-off of the low-pass filter [Hz].
CUTOFF = 6.0


def infer_labels(trial: Trial) -> list[str]:
    """The primitive moving the arm at each sample of a recorded trial, (n,)."""
    times = trial.times
    shoulder_at, elbow_at, wrist_at = (
        smooth(p, times) for p in (trial.shoulder, trial.elbow, trial.wrist)
    )
    upper = unit(elbow_at - shoulder_at)
    fore = unit(wrist_at - elbow_at)
    normal = unit(np.cross(upper, fore))
    frames = np.stack((upper, normal, np.cross(upper, normal)), axis=-1)
    shoulder = _speeds(_frame_steps(frames), times)
    flexion = np.arctan2(
        np.linalg.norm(np.cross(upper, fore), axis=1),
        np.einsum("ij,ij->i", upper, fore),
    )
    elbow = np.abs(np.gradient(flexion, times))
    roll = np.zeros_like(times)
    if trial.wrist_frame is not None:
        angle = smooth(
            np.unwrap(forearm_roll(shoulder_at, elbow_at, wrist_at, trial.wrist_frame)),
            times,
        )
        roll = np.abs(np.gradient(angle, times))
    return labels_from_motion(_moving(shoulder), _moving(elbow), _moving(roll))


def _frame_steps(frames: np.ndarray) -> np.ndarray:
    """Rotation angle between consecutive frames [rad], shape (n - 1,)."""
    relative = np.einsum("nji,njk->nik", frames[:-1], frames[1:])
    cos = (np.trace(relative, axis1=1, axis2=2) - 1.0) / 2.0
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _speeds(steps: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Per-sample speed [rad/s] from the angles between samples, shape (n,)."""
    rates = steps / np.diff(times)
    return np.concatenate(([rates[0]], 0.5 * (rates[:-1] + rates[1:]), [rates[-1]]))


def _moving(speed: np.ndarray) -> np.ndarray:
    peak = float(speed.max(initial=0.0))
    return (speed > ACTIVE * peak) & (speed > FLOOR)


def smooth(values: np.ndarray, times: np.ndarray) -> np.ndarray:
    """``values`` (shape (n, ...)) low-passed at ``CUTOFF`` with zero lag.

    Left as is when the trial is too short to filter or too slowly sampled.
    """
    rate = (len(times) - 1) / float(times[-1] - times[0])
    if len(times) < 16 or rate <= 2.0 * CUTOFF:
        return values
    # Imported here: scipy.signal takes about 0.6 s to import, and every
    # process that reads a motion model (planner, decide) imports this
    # package, but only a fit filters.
    from scipy.signal import butter, filtfilt

    b, a = butter(2, CUTOFF / (rate / 2.0))
    return np.asarray(filtfilt(b, a, values, axis=0), dtype=float)
